// `candela compare A B`: error metrics of image A against image B (exit 4 with --check beyond tolerance).
// `candela compare --batches A1 A2 ... --against B1 B2 ...|REF [--ref-stderr SE]`: the statistics
// of independent batches (engine/image/batch_stats.hpp): per-pixel z-test pass rate and z of the mean.
#include "commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "core/log.hpp"
#include "image/batch_stats.hpp"
#include "image/image.hpp"
#include "options.hpp"

namespace candela::cli {

namespace {

// Reads a batch set; every image must have the size of `first` (named in the message).
std::vector<ImageF> read_batch_set(const std::vector<std::string>& files, const std::string& first_file, int& w, int& h) {
    std::vector<ImageF> set;
    for (const std::string& f : files) {
        set.push_back(read_image(f));
        if (w == 0) w = set.back().width, h = set.back().height;
        if (set.back().width != w || set.back().height != h)
            throw bad_input(f + " is " + std::to_string(set.back().width) + "x" + std::to_string(set.back().height) +
                            " but " + first_file + " is " + std::to_string(w) + "x" + std::to_string(h));
    }
    // --spp-shard outputs carry their sample count in alpha: batches of unequal counts are not
    // identically distributed, which the statistics assume.
    for (size_t k = 1; k < set.size(); ++k)
        if (set[k].channels == 4 && set[0].channels == 4 && set[k].pixels[3] != set[0].pixels[3]) {
            log::warn(files[k] + " holds " + format_number("%g", set[k].pixels[3]) + " samples per pixel but " + files[0] +
                      " holds " + format_number("%g", set[0].pixels[3]) +
                      ": batches should have equal sample counts (--spp a multiple of the shard count)");
            break;
        }
    return set;
}

std::string z_text(double z) { return std::isinf(z) ? (z > 0 ? "inf" : "-inf") : format_number("%.3f", z); }

int cmd_compare_batches(const Args& args) {
    // The files after --batches form set A and those after --against set B (or one reference
    // image); any option ends a list.
    std::vector<std::string> a_files, b_files;
    Args rest;
    int group = 0;
    bool against = false;
    for (const std::string& arg : args) {
        if (arg == "--batches" || arg == "--against") {
            group = arg == "--batches" ? 1 : 2;
            against = against || group == 2;
        } else if (arg.size() > 1 && arg[0] == '-') {
            group = 0;
            rest.push_back(arg);
        } else if (group == 1) {
            a_files.push_back(arg);
        } else if (group == 2) {
            b_files.push_back(arg);
        } else {
            rest.push_back(arg);
        }
    }
    const Parsed p = parse(rest, {"--ref-stderr", "--z-threshold", "--z-map", "--save-mean", "--save-stderr"}, {});
    if (!p.positional.empty())
        throw bad_input("compare --batches: unexpected argument '" + p.positional.front() +
                        "' (batch files follow --batches and --against)");
    if (a_files.size() < 2)
        throw bad_input("compare --batches needs at least 2 batch images (got " + std::to_string(a_files.size()) +
                        "): the standard error is estimated from their spread");
    const bool saving = p.has("--save-mean") || p.has("--save-stderr");
    if (b_files.empty() && !saving)
        throw bad_input(against ? "compare: --against needs a reference image or at least 2 batch images"
                                : "compare --batches needs --against B1 B2 ... or --against REF (or --save-mean/--save-stderr)");
    if (p.has("--ref-stderr") && b_files.size() != 1)
        throw bad_input("--ref-stderr goes with one reference image after --against (got " + std::to_string(b_files.size()) +
                        " images)");
    const double threshold = p.has("--z-threshold") ? parse_float("--z-threshold", p.get("--z-threshold"), 1e-3f, 1e6f) : 5.0;

    int w = 0, h = 0;
    const std::vector<ImageF> a = read_batch_set(a_files, a_files[0], w, h);
    if (saving) {
        ImageF mean, se;
        batch_mean_and_stderr(a, mean, se);
        if (p.has("--save-mean")) write_image(p.get("--save-mean"), mean);
        if (p.has("--save-stderr")) write_image(p.get("--save-stderr"), se);
        if (b_files.empty()) return 0;
    }
    BatchCompareResult r;
    if (b_files.size() == 1) {
        const ImageF reference = read_batch_set(b_files, a_files[0], w, h).front();
        if (p.has("--ref-stderr")) {
            const ImageF se = read_batch_set({p.get("--ref-stderr")}, a_files[0], w, h).front();
            r = compare_batches_to_reference(a, reference, &se, threshold);
        } else {
            r = compare_batches_to_reference(a, reference, nullptr, threshold);
        }
    } else {
        r = compare_batches(a, read_batch_set(b_files, a_files[0], w, h), threshold);
    }
    const std::string b_kind = r.batches_b > 0 ? std::to_string(r.batches_b)
                                               : std::string(p.has("--ref-stderr") ? "reference+stderr" : "reference");
    std::printf("batches %d %s\n", r.batches_a, b_kind.c_str());
    std::printf("pixels %zu compared %zu nonfinite %zu\n", r.pixels, r.compared_pixels, r.nonfinite_pixels);
    std::printf("pixels_passing %.4f %% (|z| < %g)\n", 100.0 * r.passing_fraction, threshold);
    std::printf("max_abs_z %s\n", z_text(r.max_abs_z).c_str());
    std::printf("mean_a %.6g (se %.3g)\nmean_b %.6g (se %.3g)\n", r.mean_a, r.se_mean_a, r.mean_b, r.se_mean_b);
    std::printf("mean_difference %+.4f %%\n", 100.0 * r.relative_difference);
    std::printf("z_of_mean %s\n", z_text(r.z_of_mean).c_str());
    std::printf("z_of_mean_rgb %s %s %s\n", z_text(r.z_of_mean_rgb.x).c_str(), z_text(r.z_of_mean_rgb.y).c_str(),
                z_text(r.z_of_mean_rgb.z).c_str());
    if (p.has("--z-map")) {
        // |z| per pixel as a heat map: red at the threshold and beyond.
        ImageF z(w, h, 4), zero(w, h, 4);
        for (size_t i = 0; i < r.z.size(); ++i)
            for (int c = 0; c < 3; ++c) z.pixels[i * 4 + c] = std::fabs(r.z[i]);
        write_display_image(p.get("--z-map"), heatmap(z, zero, threshold));
    }
    return 0;
}

}  // namespace

int cmd_compare(const Args& args) {
    if (std::find(args.begin(), args.end(), "--batches") != args.end() ||
        std::find(args.begin(), args.end(), "--against") != args.end())
        return cmd_compare_batches(args);
    const Parsed p = parse(args, {"--heatmap", "--tolerance", "--max-failing", "--blocks"}, {"--check"});
    if (p.positional.size() != 2) throw bad_input("compare needs two images A B");
    const double tolerance = p.has("--tolerance") ? parse_float("--tolerance", p.get("--tolerance"), 0, 1e30f) : 2.0 / 255.0;
    const double max_failing = p.has("--max-failing") ? parse_float("--max-failing", p.get("--max-failing"), 0, 1) : 0.001;
    const ImageF a = read_image(p.positional[0]);
    const ImageF b = read_image(p.positional[1]);
    if (a.width != b.width || a.height != b.height)
        throw bad_input(p.positional[0] + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) + " but " +
                        p.positional[1] + " is " + std::to_string(b.width) + "x" + std::to_string(b.height));
    const CompareResult r = compare(a, b, tolerance);
    std::printf("rmse %.6g\nrelative_mse %.6g\npsnr %.3f dB\nmax_abs %.6g\nfailing_pixels %zu (%.4f %%, tolerance %.6g)\nnonfinite %zu\n",
                r.rmse, r.relative_mse, r.psnr, r.max_abs, r.failing_pixels, 100.0 * r.failing_fraction, tolerance,
                r.nonfinite);
    if (p.has("--blocks")) {
        const BlockAgreement g = block_agreement(a, b, parse_int("--blocks", p.get("--blocks"), 1, 4096));
        std::printf("block_mean_abs_display %.6g\nblock_p99_abs_display %.6g\nmean_luminance_ratio %.6g\n", g.mean_abs,
                    g.p99_abs, g.luminance_ratio);
    }
    if (p.has("--heatmap")) write_display_image(p.get("--heatmap"), heatmap(a, b, std::max(tolerance * 4, 1e-6)));
    if (p.flags.count("--check") && (r.failing_fraction > max_failing || r.nonfinite > 0)) return 4;
    return 0;
}

}  // namespace candela::cli
