#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

#include "core/error.hpp"
#include "image/image.hpp"
#include "image/image_io.hpp"
#include "image/png_write.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

// A render's .png is written with libpng (png_write.hpp) instead of OpenImageIO: the decoded
// pixels must be the ones the OpenImageIO module writes, every 8-bit value and odd widths
// (rows not a multiple of 4 bytes) included; alpha is dropped by both.
TEST(PngWrite, SamePixelsAsOpenImageIo) {
    const fs::path dir = fs::temp_directory_path() / ("candela_png_write_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const int w = 37, h = 23;
    std::vector<unsigned char> rgba(static_cast<size_t>(w) * h * 4);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<unsigned char>((i * 7919u) ^ (i >> 3));
    const fs::path ours = dir / "libpng.png", theirs = dir / "oiio.png";
    write_display_rgba8(ours, rgba, w, h);
    char error[256] = "";
    ASSERT_EQ(image_io().write_rgba8_as_rgb(theirs.c_str(), rgba.data(), w, h, error, sizeof error), 0) << error;
    const ImageF a = read_image(ours), b = read_image(theirs);
    ASSERT_EQ(a.width, w);
    ASSERT_EQ(a.height, h);
    ASSERT_EQ(b.width, w);
    ASSERT_EQ(b.height, h);
    size_t differing = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const float expected = rgba[(static_cast<size_t>(y) * w + x) * 4 + c] / 255.0f;
                EXPECT_FLOAT_EQ(a.at(x, y)[c], expected) << x << "," << y << "," << c;
                differing += a.at(x, y)[c] != b.at(x, y)[c];
            }
    EXPECT_EQ(differing, 0u);
    EXPECT_EQ(a.at(0, 0)[3], 1.0f);
    fs::remove_all(dir);
}

TEST(PngWrite, ReportsUnwritablePath) {
    const std::vector<unsigned char> rgba(4 * 4 * 4, 128);
    EXPECT_FALSE(write_png_rgb8("/nonexistent-dir/x.png", rgba.data(), 4, 4).empty());
    EXPECT_THROW(write_display_rgba8("/nonexistent-dir/x.png", rgba, 4, 4), Error);
}

}  // namespace
}  // namespace candela
