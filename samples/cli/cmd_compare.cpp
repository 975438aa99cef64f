// `candela compare A B`: error metrics of image A against image B (exit 4 with --check beyond tolerance).
#include "commands.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "image/image.hpp"
#include "options.hpp"

namespace candela::cli {

int cmd_compare(const Args& args) {
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
