#pragma once
// The C ABI between the engine and its image I/O module (libcandela_image_io.so, OpenImageIO).
// The module is loaded on first use, because OpenImageIO's dependency tree (OpenCV, GDAL, FFmpeg
// through its plugins) costs ~200 ms of process start-up here, and `info`, `--help` and most
// error paths never touch an image. (Loading it on a thread during the render was tried: on two
// cores llvmpipe already uses both, and it gained nothing measurable.) Errors come back as text;
// the engine throws.
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CANDELA_IMAGE_IO_ABI 2

typedef struct CandelaImageIoApi {
    int abi;  // CANDELA_IMAGE_IO_ABI
    // Reads RGBA float (1-4 channels expanded to 4). *pixels is allocated by the module and freed
    // with free_pixels. The image's string attributes named "candela:*" (the tags of write_float)
    // go to `tags` as "name\tvalue\n" lines, NUL-terminated (empty if none or tags_size is 0).
    // Returns 0 on success, else writes a message into error.
    int (*read_rgba_float)(const char* path, int* width, int* height, float** pixels, char* tags, size_t tags_size, char* error,
                           size_t error_size);
    void (*free_pixels)(float* pixels);
    // Writes `channels` floats per pixel (.exr/.hdr), top row first, with `tag_count` string
    // attributes (names[i] = values[i], names "candela:*") in the file's header where the format
    // has one (EXR).
    int (*write_float)(const char* path, const float* pixels, int width, int height, int channels, const char* const* names,
                       const char* const* values, size_t tag_count, char* error, size_t error_size);
    // Writes RGB of 8-bit RGBA pixels (.png), top row first.
    int (*write_rgba8_as_rgb)(const char* path, const unsigned char* rgba, int width, int height, char* error,
                              size_t error_size);
} CandelaImageIoApi;

const CandelaImageIoApi* candela_image_io_api(void);

#ifdef __cplusplus
}
#endif
