#include "image/image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "image/image_io.hpp"
#include "image/png_write.hpp"

namespace candela {
namespace fs = std::filesystem;

namespace {
std::string lower_ext(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}
}  // namespace

bool is_display_format(const fs::path& path) {
    const std::string e = lower_ext(path);
    return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".tga" || e == ".bmp";
}

ImageF read_image(const fs::path& path) {
    if (!fs::exists(path)) throw bad_input(path.string() + ": cannot read image (no such file)");
    char error[1024] = "";
    int w = 0, h = 0;
    float* pixels = nullptr;
    const CandelaImageIoApi& io = image_io();
    std::vector<char> tags(16384, '\0');
    if (io.read_rgba_float(path.c_str(), &w, &h, &pixels, tags.data(), tags.size(), error, sizeof error) != 0)
        throw bad_input(path.string() + ": " + error);
    ImageF img(w, h, 4);
    std::copy(pixels, pixels + img.pixels.size(), img.pixels.begin());
    io.free_pixels(pixels);
    for (std::string_view rest(tags.data()); !rest.empty();) {
        const size_t eol = rest.find('\n');
        const std::string_view line = rest.substr(0, eol);
        rest = eol == std::string_view::npos ? std::string_view() : rest.substr(eol + 1);
        if (const size_t tab = line.find('\t'); tab != std::string_view::npos)
            img.tags[std::string(line.substr(0, tab))] = std::string(line.substr(tab + 1));
    }
    return img;
}

glm::vec3 aces_fit(glm::vec3 x) {
    return glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

float linear_to_srgb(float c) {
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

glm::vec3 display_transform(glm::vec3 radiance, float exposure_ev) {
    const glm::vec3 t = aces_fit(glm::max(radiance, glm::vec3(0.0f)) * std::exp2(exposure_ev));
    return {linear_to_srgb(t.x), linear_to_srgb(t.y), linear_to_srgb(t.z)};
}

ImageF to_display(const ImageF& linear, float exposure_ev) {
    ImageF out(linear.width, linear.height, 4);
    for (int y = 0; y < linear.height; ++y)
        for (int x = 0; x < linear.width; ++x) {
            const float* s = linear.at(x, y);
            glm::vec3 rgb = linear.channels >= 3 ? glm::vec3(s[0], s[1], s[2]) : glm::vec3(s[0]);
            for (int c = 0; c < 3; ++c)
                if (!std::isfinite(rgb[c])) rgb[c] = 0.0f;
            const glm::vec3 d = display_transform(rgb, exposure_ev);
            float* o = out.at(x, y);
            o[0] = d.x, o[1] = d.y, o[2] = d.z, o[3] = 1.0f;
        }
    return out;
}

void write_display_rgba8(const fs::path& path, const std::vector<unsigned char>& rgba, int width, int height) {
    if (!is_display_format(path)) throw bad_input(path.string() + ": display images are written as .png");
    if (rgba.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 4)
        throw Error(ExitCode::internal, path.string() + ": display buffer size does not match " + std::to_string(width) +
                                            "x" + std::to_string(height));
    // .png without OpenImageIO (png_write.hpp says why); the other display formats through it.
    if (lower_ext(path) == ".png") {
        if (const std::string e = write_png_rgb8(path.c_str(), rgba.data(), width, height); !e.empty())
            throw bad_input(path.string() + ": " + e);
        return;
    }
    char error[1024] = "";
    if (image_io().write_rgba8_as_rgb(path.c_str(), rgba.data(), width, height, error, sizeof error) != 0)
        throw bad_input(path.string() + ": " + error);
}

void write_display_image(const fs::path& path, const ImageF& d) {
    std::vector<unsigned char> bytes(static_cast<size_t>(d.width) * d.height * 4, 255);
    for (size_t i = 0; i < static_cast<size_t>(d.width) * d.height; ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = d.pixels[i * static_cast<size_t>(d.channels) + static_cast<size_t>(std::min(c, d.channels - 1))];
            bytes[i * 4 + static_cast<size_t>(c)] =
                static_cast<unsigned char>(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
        }
    write_display_rgba8(path, bytes, d.width, d.height);
}

void write_image(const fs::path& path, const ImageF& image, float exposure_ev) {
    const std::string e = lower_ext(path);
    if (is_display_format(path)) {
        write_display_image(path, to_display(image, exposure_ev));
        return;
    }
    if (e != ".exr" && e != ".hdr") throw bad_input(path.string() + ": unknown output format '" + e + "' (use .png or .exr)");
    char error[1024] = "";
    std::vector<const char*> names, values;
    for (const auto& [name, value] : image.tags) {
        if (name.rfind("candela:", 0) != 0 || name.find_first_of("\t\n") != std::string::npos || value.find_first_of("\t\n") != std::string::npos)
            throw Error(ExitCode::internal, path.string() + ": image tag '" + name + "' must be named candela:* and hold no tab or newline");
        names.push_back(name.c_str());
        values.push_back(value.c_str());
    }
    if (image_io().write_float(path.c_str(), image.pixels.data(), image.width, image.height, image.channels, names.data(), values.data(),
                               names.size(), error, sizeof error) != 0)
        throw bad_input(path.string() + ": " + error);
}

std::size_t count_nonfinite(const ImageF& image) {
    return static_cast<std::size_t>(std::count_if(image.pixels.begin(), image.pixels.end(), [](float v) { return !std::isfinite(v); }));
}

double mean_luminance(const ImageF& img) {
    double sum = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.at(x, y);
            sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        }
    return sum / std::max(1.0, static_cast<double>(img.width) * img.height);
}

namespace {

ImageF display_blocks(const ImageF& linear, int k) {
    const ImageF d = to_display(linear, 0.0f);
    ImageF out(d.width / k, d.height / k, 3);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double s = 0;
                for (int j = 0; j < k; ++j)
                    for (int i = 0; i < k; ++i) s += d.at(x * k + i, y * k + j)[c];
                out.at(x, y)[c] = static_cast<float>(s / (k * k));
            }
    return out;
}
}  // namespace

BlockAgreement block_agreement(const ImageF& a, const ImageF& b, int k) {
    if (a.width != b.width || a.height != b.height)
        throw bad_input("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
                        std::to_string(b.width) + "x" + std::to_string(b.height));
    if (k < 1 || a.width < k || a.height < k) throw bad_input("--blocks " + std::to_string(k) + " must be in [1, image size]");
    BlockAgreement r;
    r.luminance_ratio = mean_luminance(a) / std::max(mean_luminance(b), 1e-12);
    const ImageF da = display_blocks(a, k), db = display_blocks(b, k);
    std::vector<double> worst;
    double sum = 0, bsum = 0;
    for (int y = 0; y < da.height; ++y)
        for (int x = 0; x < da.width; ++x) {
            double w = 0;
            for (int c = 0; c < 3; ++c) {
                const double d = std::fabs(static_cast<double>(da.at(x, y)[c]) - db.at(x, y)[c]);
                sum += d;
                w = std::max(w, d);
                bsum += db.at(x, y)[c];
            }
            worst.push_back(w);
        }
    const double n = static_cast<double>(da.width) * da.height * 3;
    r.mean_abs = sum / n;
    r.b_display_mean = bsum / n;
    std::sort(worst.begin(), worst.end());
    r.p99_abs = worst[static_cast<size_t>(0.99 * static_cast<double>(worst.size() - 1))];
    return r;
}

BlockBias block_bias(const ImageF& a, const ImageF& r1, const ImageF& r2, int k) {
    for (const ImageF* r : {&r1, &r2})
        if (a.width != r->width || a.height != r->height)
            throw bad_input("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
                            std::to_string(r->width) + "x" + std::to_string(r->height));
    if (k < 1 || a.width < k || a.height < k) throw bad_input("--blocks " + std::to_string(k) + " must be in [1, image size]");
    const auto block_mean = [k](const ImageF& img, int bx, int by) {
        glm::dvec3 s(0.0);
        for (int j = 0; j < k; ++j)
            for (int i = 0; i < k; ++i) {
                const float* p = img.at(bx * k + i, by * k + j);
                for (int c = 0; c < 3; ++c) {
                    const float v = p[std::min(c, img.channels - 1)];
                    s[c] += std::isfinite(v) ? static_cast<double>(v) : 0.0;
                }
            }
        return s / static_cast<double>(k * k);
    };
    double cross = 0, naive = 0, noise = 0;
    const int bw = a.width / k, bh = a.height / k;
    for (int by = 0; by < bh; ++by)
        for (int bx = 0; bx < bw; ++bx) {
            const glm::dvec3 ma = block_mean(a, bx, by), m1 = block_mean(r1, bx, by), m2 = block_mean(r2, bx, by);
            const glm::dvec3 mu = 0.5 * (m1 + m2);
            for (int c = 0; c < 3; ++c) {
                // The display transform's slope in this channel at the raster's value: taken at
                // the reference's, it would correlate with the reference's noise and bias the
                // cross product (the display curve is steeper where the noise made it darker).
                const double h = std::max(1e-4, 1e-3 * std::fabs(ma[c]));
                glm::vec3 lo = glm::vec3(glm::max(ma, glm::dvec3(0.0))), hi = lo;
                lo[c] = static_cast<float>(std::max(ma[c] - h, 0.0));
                hi[c] = static_cast<float>(std::max(ma[c], 0.0) + h);
                const double slope = (display_transform(hi, 0.0f)[c] - display_transform(lo, 0.0f)[c]) / static_cast<double>(hi[c] - lo[c]);
                const double e1 = (ma[c] - m1[c]) * slope, e2 = (ma[c] - m2[c]) * slope, e = (ma[c] - mu[c]) * slope;
                const double d = (m1[c] - m2[c]) * slope;
                cross += e1 * e2;
                naive += e * e;
                noise += 0.25 * d * d;  // the variance of (r1 + r2) / 2: that of r1 - r2 over 4
            }
        }
    const double n = std::max(1.0, static_cast<double>(bw) * bh * 3);
    BlockBias r;
    r.rms = std::sqrt(std::max(cross / n, 0.0));
    r.naive_rms = std::sqrt(naive / n);
    r.ref_noise_rms = std::sqrt(noise / n);
    return r;
}

double rmse(const ImageF& a, const ImageF& b) { return compare(a, b, 0.0).rmse; }

CompareResult compare(const ImageF& actual, const ImageF& expected, double tolerance) {
    if (actual.width != expected.width || actual.height != expected.height)
        throw bad_input("images differ in size: " + std::to_string(actual.width) + "x" + std::to_string(actual.height) +
                        " vs " + std::to_string(expected.width) + "x" + std::to_string(expected.height));
    CompareResult r;
    r.nonfinite = count_nonfinite(actual) + count_nonfinite(expected);
    double se = 0, rel = 0;
    const size_t n = static_cast<size_t>(actual.width) * actual.height;
    for (size_t i = 0; i < n; ++i) {
        bool fails = false;
        for (int c = 0; c < 3; ++c) {
            const double a = actual.pixels[i * static_cast<size_t>(actual.channels) + static_cast<size_t>(std::min(c, actual.channels - 1))];
            const double b = expected.pixels[i * static_cast<size_t>(expected.channels) + static_cast<size_t>(std::min(c, expected.channels - 1))];
            const double d = std::isfinite(a) && std::isfinite(b) ? a - b : std::numeric_limits<double>::infinity();
            const double ad = std::fabs(d);
            se += std::isfinite(ad) ? d * d : 0.0;
            rel += std::isfinite(ad) ? d * d / (b * b + 1e-2) : 0.0;
            r.max_abs = std::max(r.max_abs, ad);
            // Small slack so that 8-bit quantisation of exactly `tolerance` still passes.
            if (!(ad <= tolerance + 1e-6)) fails = true;
        }
        if (fails) ++r.failing_pixels;
    }
    const double count = static_cast<double>(std::max<size_t>(n * 3, 1));
    r.rmse = std::sqrt(se / count);
    r.relative_mse = rel / count;
    r.psnr = r.rmse > 0 ? 20.0 * std::log10(1.0 / r.rmse) : std::numeric_limits<double>::infinity();
    r.failing_fraction = n ? static_cast<double>(r.failing_pixels) / static_cast<double>(n) : 0.0;
    return r;
}

ImageF heatmap(const ImageF& actual, const ImageF& expected, double scale) {
    ImageF out(actual.width, actual.height, 4);
    if (actual.width != expected.width || actual.height != expected.height) return out;
    for (int y = 0; y < actual.height; ++y)
        for (int x = 0; x < actual.width; ++x) {
            double d = 0;
            for (int c = 0; c < 3; ++c) {
                const double v = std::fabs(static_cast<double>(actual.at(x, y)[std::min(c, actual.channels - 1)]) -
                                           expected.at(x, y)[std::min(c, expected.channels - 1)]);
                d = std::max(d, std::isfinite(v) ? v : 1e30);
            }
            const float t = static_cast<float>(std::clamp(d / std::max(scale, 1e-12), 0.0, 1.0));
            // Piecewise ramp: 0 black, 0.25 blue, 0.5 green, 0.75 yellow, 1 red.
            const glm::vec3 stops[5] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
            const float s = t * 4.0f;
            const int i = std::min(static_cast<int>(s), 3);
            const glm::vec3 col = glm::mix(stops[i], stops[i + 1], s - static_cast<float>(i));
            float* o = out.at(x, y);
            o[0] = col.x, o[1] = col.y, o[2] = col.z, o[3] = 1.0f;
        }
    return out;
}

}  // namespace candela
