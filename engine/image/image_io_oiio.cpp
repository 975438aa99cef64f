// The image I/O module: every OpenImageIO call of Candela, behind image_io_api.h.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "image/image_io_api.h"

namespace {

int fail(char* error, size_t size, const std::string& message) {
    std::snprintf(error, size, "%s", message.c_str());
    return 1;
}

int read_rgba_float(const char* path, int* width, int* height, float** pixels, char* tags, size_t tags_size, char* error,
                    size_t error_size) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return fail(error, error_size, "cannot read image (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.width > 65536 || spec.height > 65536 || spec.nchannels <= 0)
        return fail(error, error_size, "unsupported image size or channel count");
    const size_t n = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
    std::vector<float> raw(n * static_cast<size_t>(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, raw.data()))
        return fail(error, error_size, "cannot decode image (" + in->geterror() + ")");
    auto* out = static_cast<float*>(std::malloc(n * 4 * sizeof(float)));
    if (!out) return fail(error, error_size, "out of memory");
    for (size_t i = 0; i < n; ++i) {
        const float* s = raw.data() + i * static_cast<size_t>(spec.nchannels);
        float* d = out + i * 4;
        if (spec.nchannels >= 3) d[0] = s[0], d[1] = s[1], d[2] = s[2];
        else d[0] = d[1] = d[2] = s[0];
        d[3] = spec.nchannels == 4 ? s[3] : spec.nchannels == 2 ? s[1] : 1.0f;
    }
    if (tags_size > 0) {
        std::string lines;
        for (const OIIO::ParamValue& a : spec.extra_attribs)
            if (a.type() == OIIO::TypeDesc::STRING && a.name().string().rfind("candela:", 0) == 0)
                lines += a.name().string() + "\t" + a.get_string() + "\n";
        if (lines.size() >= tags_size) {
            std::free(out);
            return fail(error, error_size, "the image's candela:* attributes are too long");
        }
        std::memcpy(tags, lines.c_str(), lines.size() + 1);
    }
    *width = spec.width;
    *height = spec.height;
    *pixels = out;
    return 0;
}

void free_pixels(float* pixels) { std::free(pixels); }

int write_float(const char* path, const float* pixels, int width, int height, int channels, const char* const* names,
                const char* const* values, size_t tag_count, char* error, size_t error_size) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return fail(error, error_size, "cannot write this format (" + OIIO::geterror() + ")");
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    for (size_t i = 0; i < tag_count; ++i) spec.attribute(names[i], values[i]);
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels) || !out->close())
        return fail(error, error_size, "cannot write (" + out->geterror() + ")");
    return 0;
}

int write_rgba8_as_rgb(const char* path, const unsigned char* rgba, int width, int height, char* error, size_t error_size) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return fail(error, error_size, "cannot write this format (" + OIIO::geterror() + ")");
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    // zlib level 6 (the default) costs ~100 ms at 1280x720 on this CPU; level 1 writes files
    // ~20 % larger in a fraction of the time.
    spec.attribute("png:compressionLevel", 1);
    // RGBA in memory, RGB in the file: a 4-byte pixel stride over the first 3 channels.
    if (!out->open(path, spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, rgba, 4, static_cast<OIIO::stride_t>(width) * 4) || !out->close())
        return fail(error, error_size, "cannot write (" + out->geterror() + ")");
    return 0;
}

const CandelaImageIoApi kApi = {CANDELA_IMAGE_IO_ABI, read_rgba_float, free_pixels, write_float, write_rgba8_as_rgb};

}  // namespace

extern "C" __attribute__((visibility("default"))) const CandelaImageIoApi* candela_image_io_api(void) { return &kApi; }
