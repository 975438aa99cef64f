#include "image/batch_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace candela {

BatchMean batch_mean(const std::vector<double>& values) {
    BatchMean m;
    const auto n = static_cast<double>(values.size());
    if (values.empty()) return m;
    for (double x : values) m.mean += x / n;
    if (values.size() < 2) return m;
    double ss = 0.0;
    for (double x : values) ss += (x - m.mean) * (x - m.mean);
    m.se = std::sqrt(ss / (n - 1.0) / n);
    return m;
}

namespace {

constexpr glm::dvec3 kLuminance{0.2126, 0.7152, 0.0722};  // Rec. 709 / sRGB primaries

glm::dvec3 rgb_of(const ImageF& image, std::size_t i) {
    const float* p = image.pixels.data() + i * static_cast<std::size_t>(image.channels);
    return image.channels >= 3 ? glm::dvec3(p[0], p[1], p[2]) : glm::dvec3(p[0]);
}

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_set(const std::vector<ImageF>& set, const char* name) {
    if (set.size() < 2)
        throw bad_input(std::string("batch set ") + name + " has " + std::to_string(set.size()) +
                        " image(s); the standard error needs at least 2 batches");
    for (std::size_t k = 0; k < set.size(); ++k) {
        const ImageF& im = set[k];
        if (im.width != set[0].width || im.height != set[0].height)
            throw bad_input(std::string("batch set ") + name + ": batch " + std::to_string(k) + " is " +
                            std::to_string(im.width) + "x" + std::to_string(im.height) + " but batch 0 is " +
                            std::to_string(set[0].width) + "x" + std::to_string(set[0].height));
        if (im.channels < 1 || im.pixels.size() != static_cast<std::size_t>(im.width) * im.height * im.channels)
            throw bad_input(std::string("batch set ") + name + ": batch " + std::to_string(k) + " has no pixel data");
    }
}

void check_same_size(const ImageF& a, const ImageF& b, const std::string& what) {
    if (a.width != b.width || a.height != b.height)
        throw bad_input(what + " is " + std::to_string(b.width) + "x" + std::to_string(b.height) + " but the batches are " +
                        std::to_string(a.width) + "x" + std::to_string(a.height));
}

// One side of a comparison: per-pixel means and variances of those means (RGB), and the image
// mean's variance given the set of compared pixels.
struct Side {
    std::vector<glm::dvec3> mean;
    std::vector<glm::dvec3> var;  // se^2 of the mean
};

// valid[i] is cleared where any batch has a non-finite RGB value.
Side batch_side(const std::vector<ImageF>& set, std::vector<unsigned char>& valid) {
    const std::size_t n = valid.size();
    const double count = static_cast<double>(set.size());
    Side s;
    s.mean.assign(n, glm::dvec3(0.0));
    s.var.assign(n, glm::dvec3(0.0));
    for (const ImageF& im : set)
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec3 v = rgb_of(im, i);
            if (!finite3(v)) valid[i] = 0;
            else s.mean[i] += v;
        }
    for (std::size_t i = 0; i < n; ++i) s.mean[i] /= count;
    // Two passes (mean, then squared deviations): no cancellation on bright, low-noise pixels.
    for (const ImageF& im : set)
        for (std::size_t i = 0; i < n; ++i)
            if (valid[i]) {
                const glm::dvec3 d = rgb_of(im, i) - s.mean[i];
                s.var[i] += d * d;
            }
    for (std::size_t i = 0; i < n; ++i) s.var[i] /= (count - 1.0) * count;  // s^2 / N
    return s;
}

// Each batch's mean over the valid pixels (RGB).
std::vector<glm::dvec3> batch_image_means(const std::vector<ImageF>& set, const std::vector<unsigned char>& valid,
                                          std::size_t compared) {
    std::vector<glm::dvec3> per_batch;
    for (const ImageF& im : set) {
        glm::dvec3 sum(0.0);
        for (std::size_t i = 0; i < valid.size(); ++i)
            if (valid[i]) sum += rgb_of(im, i);
        per_batch.push_back(compared > 0 ? sum / static_cast<double>(compared) : glm::dvec3(0.0));
    }
    return per_batch;
}

double z_of(double difference, double variance) {
    if (variance > 0) return difference / std::sqrt(variance);
    if (difference == 0) return 0.0;
    return difference > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
}

struct SideMeans {
    glm::dvec3 rgb{0.0};
    glm::dvec3 var_rgb{0.0};
    double var_luminance = 0;
};

BatchCompareResult finish(const Side& a, const Side& b, const std::vector<unsigned char>& valid, const SideMeans& ma,
                          const SideMeans& mb, double z_threshold) {
    BatchCompareResult r;
    r.z_threshold = z_threshold;
    r.pixels = valid.size();
    r.z.assign(valid.size(), 0.0f);
    for (std::size_t i = 0; i < valid.size(); ++i) {
        if (!valid[i]) {
            ++r.nonfinite_pixels;
            continue;
        }
        ++r.compared_pixels;
        bool pass = true;
        double worst = 0;
        for (int c = 0; c < 3; ++c) {
            const double z = z_of(a.mean[i][c] - b.mean[i][c], a.var[i][c] + b.var[i][c]);
            if (!(std::fabs(z) < z_threshold)) pass = false;
            if (std::fabs(z) > std::fabs(worst)) worst = z;
        }
        r.max_abs_z = std::max(r.max_abs_z, std::fabs(worst));
        r.z[i] = static_cast<float>(worst);
        if (pass) ++r.passing_pixels;
    }
    r.passing_fraction = r.compared_pixels > 0 ? static_cast<double>(r.passing_pixels) / static_cast<double>(r.compared_pixels) : 1.0;
    r.mean_a_rgb = ma.rgb;
    r.mean_b_rgb = mb.rgb;
    r.mean_a = glm::dot(kLuminance, ma.rgb);
    r.mean_b = glm::dot(kLuminance, mb.rgb);
    r.se_mean_a = std::sqrt(ma.var_luminance);
    r.se_mean_b = std::sqrt(mb.var_luminance);
    r.relative_difference = r.mean_b != 0 ? (r.mean_a - r.mean_b) / r.mean_b : 0.0;
    r.z_of_mean = z_of(r.mean_a - r.mean_b, ma.var_luminance + mb.var_luminance);
    for (int c = 0; c < 3; ++c) r.z_of_mean_rgb[c] = z_of(ma.rgb[c] - mb.rgb[c], ma.var_rgb[c] + mb.var_rgb[c]);
    return r;
}

std::size_t count_valid(const std::vector<unsigned char>& valid) {
    std::size_t n = 0;
    for (unsigned char v : valid) n += v;
    return n;
}

// The image mean of a batch set and its variance: the sample variance of the N batches' image
// means over N (the batches are independent; the pixels within one are not). Luminance is a
// linear function of RGB, so a batch's luminance mean is that of its RGB mean; its variance is
// taken from those N values directly, which keeps the channels' correlation.
SideMeans batch_means(const std::vector<ImageF>& set, const std::vector<unsigned char>& valid, std::size_t compared) {
    const std::vector<glm::dvec3> per_batch = batch_image_means(set, valid, compared);
    const double count = static_cast<double>(per_batch.size());
    SideMeans m;
    for (const glm::dvec3& b : per_batch) m.rgb += b;
    m.rgb /= count;
    const double lum = glm::dot(kLuminance, m.rgb);
    for (const glm::dvec3& b : per_batch) {
        m.var_rgb += (b - m.rgb) * (b - m.rgb);
        const double d = glm::dot(kLuminance, b) - lum;
        m.var_luminance += d * d;
    }
    m.var_rgb /= (count - 1.0) * count;
    m.var_luminance /= (count - 1.0) * count;
    return m;
}

}  // namespace

BatchCompareResult compare_batches(const std::vector<ImageF>& a, const std::vector<ImageF>& b, double z_threshold) {
    check_set(a, "A");
    check_set(b, "B");
    check_same_size(a[0], b[0], "batch set B");
    std::vector<unsigned char> valid(static_cast<std::size_t>(a[0].width) * a[0].height, 1);
    const Side sa = batch_side(a, valid);
    const Side sb = batch_side(b, valid);
    const std::size_t compared = count_valid(valid);
    BatchCompareResult r = finish(sa, sb, valid, batch_means(a, valid, compared), batch_means(b, valid, compared), z_threshold);
    r.batches_a = static_cast<int>(a.size());
    r.batches_b = static_cast<int>(b.size());
    return r;
}

BatchCompareResult compare_batches_to_reference(const std::vector<ImageF>& a, const ImageF& reference,
                                                const ImageF* reference_stderr, double z_threshold) {
    check_set(a, "A");
    check_same_size(a[0], reference, "the reference");
    if (reference_stderr) check_same_size(a[0], *reference_stderr, "the reference's standard-error image");
    const std::size_t n = static_cast<std::size_t>(a[0].width) * a[0].height;
    std::vector<unsigned char> valid(n, 1);
    const Side sa = batch_side(a, valid);
    Side sr;
    sr.mean.resize(n);
    sr.var.assign(n, glm::dvec3(0.0));
    for (std::size_t i = 0; i < n; ++i) {
        sr.mean[i] = rgb_of(reference, i);
        if (!finite3(sr.mean[i])) valid[i] = 0;
        if (reference_stderr) {
            const glm::dvec3 se = rgb_of(*reference_stderr, i);
            if (!finite3(se)) valid[i] = 0;
            else sr.var[i] = se * se;
        }
    }
    const std::size_t compared = count_valid(valid);
    SideMeans mr;
    for (std::size_t i = 0; i < n; ++i)
        if (valid[i]) {
            mr.rgb += sr.mean[i];
            mr.var_rgb += sr.var[i];
        }
    if (compared > 0) {
        const double p = static_cast<double>(compared);
        mr.rgb /= p;
        mr.var_rgb /= p * p;  // independent pixels: var(mean) = sum(se^2) / P^2
    }
    // Channels treated as independent too: nothing else is known of the reference.
    mr.var_luminance = glm::dot(kLuminance * kLuminance, mr.var_rgb);
    BatchCompareResult r = finish(sa, sr, valid, batch_means(a, valid, compared), mr, z_threshold);
    r.batches_a = static_cast<int>(a.size());
    r.batches_b = 0;
    return r;
}

void batch_mean_and_stderr(const std::vector<ImageF>& batches, ImageF& mean, ImageF& stderr_image) {
    check_set(batches, "A");
    std::vector<unsigned char> valid(static_cast<std::size_t>(batches[0].width) * batches[0].height, 1);
    const Side s = batch_side(batches, valid);
    mean = ImageF(batches[0].width, batches[0].height, 4);
    stderr_image = ImageF(batches[0].width, batches[0].height, 4);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t i = 0; i < valid.size(); ++i) {
        float* m = mean.pixels.data() + i * 4;
        float* e = stderr_image.pixels.data() + i * 4;
        for (int c = 0; c < 3; ++c) {
            // A pixel some batch has no finite value for stays non-finite, so that a comparison
            // against this reference leaves it out too.
            m[c] = valid[i] ? static_cast<float>(s.mean[i][c]) : nan;
            e[c] = valid[i] ? static_cast<float>(std::sqrt(s.var[i][c])) : nan;
        }
        m[3] = e[3] = 1.0f;
    }
}

}  // namespace candela
