#include "image/image_io.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "core/error.hpp"

#ifndef CANDELA_IMAGE_IO_NAME
#define CANDELA_IMAGE_IO_NAME "libcandela_image_io.so"
#endif
#ifndef CANDELA_IMAGE_IO_BUILD_DIR
#define CANDELA_IMAGE_IO_BUILD_DIR ""
#endif

namespace candela {
namespace fs = std::filesystem;
namespace {

std::once_flag g_once;
const CandelaImageIoApi* g_api = nullptr;
std::string g_error;

fs::path executable_dir() {
    char buf[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return {};
    buf[n] = '\0';
    return fs::path(buf).parent_path();
}

void load() {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("CANDELA_IMAGE_IO"); env && *env) candidates.emplace_back(env);
    const fs::path exe = executable_dir();
    if (!exe.empty()) candidates.push_back((exe.parent_path() / "lib" / CANDELA_IMAGE_IO_NAME).string());
    if (*CANDELA_IMAGE_IO_BUILD_DIR) candidates.push_back((fs::path(CANDELA_IMAGE_IO_BUILD_DIR) / CANDELA_IMAGE_IO_NAME).string());
    candidates.emplace_back(CANDELA_IMAGE_IO_NAME);  // the dynamic linker's search path
    std::string tried;
    for (const std::string& path : candidates) {
        if (path.find('/') != std::string::npos && !fs::exists(path)) {
            tried += "\n  " + path + ": no such file";
            continue;
        }
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            tried += "\n  " + path + ": " + dlerror();
            continue;
        }
        using Entry = const CandelaImageIoApi* (*)();
        auto entry = reinterpret_cast<Entry>(dlsym(handle, "candela_image_io_api"));
        const CandelaImageIoApi* api = entry ? entry() : nullptr;
        if (!api || api->abi != CANDELA_IMAGE_IO_ABI) {
            tried += "\n  " + path + ": not a Candela image I/O module of ABI " + std::to_string(CANDELA_IMAGE_IO_ABI);
            continue;
        }
        g_api = api;  // the module stays loaded for the life of the process
        return;
    }
    g_error = "cannot load the image I/O module " + std::string(CANDELA_IMAGE_IO_NAME) +
              " (set CANDELA_IMAGE_IO to its path); tried:" + tried;
}

}  // namespace

bool image_io_built() {
#ifdef CANDELA_NO_IMAGE_IO
    return false;
#else
    return true;
#endif
}

const CandelaImageIoApi& image_io() {
#ifdef CANDELA_NO_IMAGE_IO
    // The render-only build (README's first command) does not install OpenImageIO: .png output
    // goes through libpng, everything else needs the module.
    throw Error(ExitCode::bad_input,
                "this candela was built without OpenImageIO: writing .exr/.hdr and reading images need it "
                "(install libopenimageio-dev, e.g. bash .ci/setup, then configure and build again)");
#endif
    std::call_once(g_once, load);
    if (!g_api) throw Error(ExitCode::internal, g_error);
    return *g_api;
}

}  // namespace candela
