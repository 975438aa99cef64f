#pragma once
// Linear float images, their I/O through OpenImageIO, the display transform, and the one
// image comparison of the project (golden tests, `candela compare`, reference agreement).
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace candela {

struct ImageF {
    int width = 0;
    int height = 0;
    int channels = 4;
    std::vector<float> pixels;  // row-major, top row first
    // Named strings carried in an .exr's header ("candela:*" names): what a --spp-shard output
    // is a shard of (scene, mode, seed, spp, shard), so that merges refuse shards that differ.
    std::map<std::string, std::string> tags;

    ImageF() = default;
    ImageF(int w, int h, int c) : width(w), height(h), channels(c), pixels(static_cast<size_t>(w) * h * c, 0.0f) {}
    float* at(int x, int y) { return pixels.data() + (static_cast<size_t>(y) * width + x) * channels; }
    const float* at(int x, int y) const { return pixels.data() + (static_cast<size_t>(y) * width + x) * channels; }
    bool empty() const { return pixels.empty(); }
};

// Reads any format OpenImageIO knows (PNG/JPEG as [0,1] display values, EXR/HDR as linear).
// Throws candela::Error (bad_input) naming the file.
ImageF read_image(const std::filesystem::path& path);

// .exr: linear float radiance as is. .png/.jpg/.tga: display transform (exposure + ACES + sRGB)
// to 8 bits. Throws candela::Error (bad_input) for an unknown extension or an unwritable path.
void write_image(const std::filesystem::path& path, const ImageF& image, float exposure_ev = 0.0f);
bool is_display_format(const std::filesystem::path& path);
// Writes values already in display space ([0,1], e.g. a heat map) to an 8-bit PNG.
void write_display_image(const std::filesystem::path& path, const ImageF& display);
// Writes 8-bit RGBA display values (e.g. from the GPU tonemap pass) as an RGB .png.
void write_display_rgba8(const std::filesystem::path& path, const std::vector<unsigned char>& rgba, int width, int height);

// Exposure (EV) + ACES filmic fit (Narkowicz 2015) + sRGB OETF; the twin of tonemap.glsl.
glm::vec3 aces_fit(glm::vec3 x);
float linear_to_srgb(float c);
glm::vec3 display_transform(glm::vec3 radiance, float exposure_ev);
ImageF to_display(const ImageF& linear, float exposure_ev);  // values in [0,1]

// Every image a test writes is scanned with this.
std::size_t count_nonfinite(const ImageF& image);
// Mean linear luminance (Rec. 709 weights) over every pixel; 0 for an empty image.
double mean_luminance(const ImageF& image);
// Root mean square difference over the RGB channels of two images of one size (compare's rmse).
double rmse(const ImageF& a, const ImageF& b);

struct CompareResult {
    double rmse = 0;          // over all channels compared (RGB)
    double relative_mse = 0;  // mean of (a-b)^2 / (b^2 + 1e-2)
    double psnr = 0;          // dB, peak 1.0; infinity when identical
    double max_abs = 0;
    std::size_t failing_pixels = 0;  // pixels with any channel differing by more than tolerance
    double failing_fraction = 0;
    std::size_t nonfinite = 0;       // non-finite values in either image
};

// Compares RGB of two images of equal size (throws bad_input otherwise).
CompareResult compare(const ImageF& actual, const ImageF& expected, double tolerance);

// How a raster image agrees with a noisy reference (the path tracer) as a viewer sees them: both
// tone-mapped to display values (exposure 0), averaged over k x k blocks (which takes out most of
// the reference's per-pixel noise), then compared. Used by model_tests and `compare --blocks K`.
struct BlockAgreement {
    double mean_abs = 0;        // mean |a - b| over blocks and RGB channels
    double p99_abs = 0;         // 99th percentile over blocks of the largest channel difference
    double luminance_ratio = 0; // mean linear luminance of a / of b
    double b_display_mean = 0;  // mean display value of b (a black or unlit reference is ~0)
};
BlockAgreement block_agreement(const ImageF& a, const ImageF& b, int k);

// The raster's error against the expected value of a noisy reference, with the reference's
// noise taken out: from two independent reference renders r1 and r2 (different seeds, equal
// samples), over k x k blocks of linear radiance, E[(a - r1)(a - r2)] = (a - mu)^2 whatever the
// noise, since the two errors are independent. Each block's difference is carried to display
// values by the display transform's slope at the raster's block mean (first order, exposure
// 0), so the figures read like block_agreement's. `rms`: the square root of the mean over blocks
// and RGB of the cross product (0 if noise makes it negative); `naive_rms`: the same against
// (r1 + r2) / 2 without the noise taken out; `ref_noise_rms`: the standard error of that mean.
struct BlockBias {
    double rms = 0;
    double naive_rms = 0;
    double ref_noise_rms = 0;
};
BlockBias block_bias(const ImageF& a, const ImageF& r1, const ImageF& r2, int k);

// Per-pixel max channel difference as a heat map (black 0 -> blue -> green -> yellow -> red at
// `scale`), display values.
ImageF heatmap(const ImageF& actual, const ImageF& expected, double scale);

}  // namespace candela
