// Mesa's off-screen context. Its own tiny colour buffer is never read: rendering goes to FBOs.
#include <GL/osmesa.h>

#include <array>

#include "platform/context.hpp"

namespace candela::detail {
namespace {

class OsMesaShared final : public SharedContext {
public:
    explicit OsMesaShared(OSMesaContext context) : context_(context) {}
    ~OsMesaShared() override { OSMesaDestroyContext(context_); }
    bool make_current() override { return OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1) != 0; }
    void release() override { OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0); }

private:
    OSMesaContext context_;
    std::array<unsigned char, 4> buffer_{};
};

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
    std::unique_ptr<SharedContext> create_shared() override {
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                               OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        OSMesaContext shared = OSMesaCreateContextAttribs(attribs, context_);
        if (!shared) return nullptr;
        return std::make_unique<OsMesaShared>(shared);
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

// After a failed 4.5 request: the best core context the driver does give (Mesa answers a 3.2
// request with its highest core version), asked what it lacks.
std::string diagnose_osmesa() {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 2, 0};
    OSMesaContext probe = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!probe) return "osmesa: could not create an OpenGL 4.5 core context (OSMesaCreateContextAttribs failed, and no core context at all is offered)";
    std::array<unsigned char, 4 * 4 * 4> buffer{};
    std::string text = "osmesa: could not create an OpenGL 4.5 core context";
    if (OSMesaMakeCurrent(probe, buffer.data(), GL_UNSIGNED_BYTE, 4, 4))
        text = describe_shortfall("osmesa", reinterpret_cast<GetProcAddress>(OSMesaGetProcAddress));
    OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
    OSMesaDestroyContext(probe);
    return text;
}

}  // namespace

std::unique_ptr<Context> create_osmesa(const ContextOptions& options, std::string& error) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                           OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
    OSMesaContext context = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!context) {
        error = diagnose_osmesa();
        return nullptr;
    }
    auto result = std::make_unique<OsMesaContext>(context, options.debug);
    error = result->init();
    if (!error.empty()) return nullptr;
    return result;
}

}  // namespace candela::detail
