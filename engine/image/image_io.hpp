#pragma once
// Loading of the image I/O module (image_io_api.h). image_io() loads it once (thread-safe) and
// throws candela::Error (internal) naming where it looked if it cannot.

#include "image/image_io_api.h"

namespace candela {

const CandelaImageIoApi& image_io();

// False in a build without OpenImageIO (the README's render-only build): image_io() then throws
// (bad input) saying what needs it; callers check first so that they fail before the work.
bool image_io_built();

}  // namespace candela
