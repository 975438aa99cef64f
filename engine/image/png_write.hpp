#pragma once
// Writes 8-bit RGBA pixels (top row first) as an 8-bit RGB .png with libpng. A render's .png goes
// through here instead of the OpenImageIO module: dlopen of OpenImageIO (with its OpenCV, GDAL,
// FFmpeg... dependencies) took 0.25-0.36 s of a 1280x720 render's process, the encode ~30 ms.
// The decoded pixels are the ones OpenImageIO wrote (test_png_write); OpenImageIO stays for
// reading and for .exr/.hdr and the other display formats.
#include <string>

namespace candela {

// Returns an empty string on success, else what went wrong.
std::string write_png_rgb8(const char* path, const unsigned char* rgba, int width, int height);

}  // namespace candela
