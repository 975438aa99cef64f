// Mesa's off-screen context. Its own tiny colour buffer is never read: rendering goes to FBOs.
#include <GL/osmesa.h>

#include <array>

#include "platform/context.hpp"

namespace candela::detail {
namespace {

class OsMesaContext final : public Context {
public:
    OsMesaContext(OSMesaContext context, bool debug) : context_(context), debug_(debug) {}
    ~OsMesaContext() override { OSMesaDestroyContext(context_); }
    Backend backend() const override { return Backend::osmesa; }
    bool make_current() override {
        if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize)) return false;
        std::string r, v;
        return load_gl_and_check("osmesa", reinterpret_cast<GetProcAddress>(OSMesaGetProcAddress),
                                 r, v, false)
            .empty();
    }
    std::string init() {
        if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize))
            return "osmesa: OSMesaMakeCurrent failed";
        return load_gl_and_check("osmesa", reinterpret_cast<GetProcAddress>(OSMesaGetProcAddress),
                                 renderer_, version_, debug_);
    }

private:
    static constexpr int kSize = 16;
    OSMesaContext context_;
    bool debug_;
    std::array<unsigned char, kSize * kSize * 4> buffer_{};
};

}  // namespace

std::unique_ptr<Context> create_osmesa(const ContextOptions& options, std::string& error) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                           OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
    OSMesaContext context = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!context) {
        error = "osmesa: could not create an OpenGL 4.5 core context (OSMesaCreateContextAttribs failed)";
        return nullptr;
    }
    auto result = std::make_unique<OsMesaContext>(context, options.debug);
    error = result->init();
    if (!error.empty()) return nullptr;
    return result;
}

}  // namespace candela::detail
