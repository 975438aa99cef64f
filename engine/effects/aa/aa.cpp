#include "effects/aa/aa.hpp"

#include <algorithm>
#include <cmath>

#include <glad/gl.h>

#include "effects/aa/aa_data.h"
#include "effects/aa/aa_sweep.hpp"
#include "effects/transparency/transparency.hpp"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

// Rook patterns for sub-frames of single-sample targets (pixel units from the centre, y up): the
// standard 2, 4 and 8 sample positions of Direct3D's multisampling (1/16 pixel grid).
const std::vector<glm::vec2>& rook_pattern(int n) {
    static const std::vector<glm::vec2> p2 = {{4, 4}, {-4, -4}};
    static const std::vector<glm::vec2> p4 = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
    static const std::vector<glm::vec2> p8 = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
    static std::vector<glm::vec2> s2, s4, s8;
    auto scaled = [](const std::vector<glm::vec2>& p, std::vector<glm::vec2>& out) -> const std::vector<glm::vec2>& {
        if (out.empty())
            for (glm::vec2 v : p) out.push_back(v / 16.0f);
        return out;
    };
    return n == 2 ? scaled(p2, s2) : n == 4 ? scaled(p4, s4) : scaled(p8, s8);
}

// Quality of a pattern in the unit pixel (positions in [0,1)): distinct columns and rows on the
// 1/64 grid first (edges near the axes), then the smallest distance between two samples.
std::pair<int, float> pattern_score(const std::vector<glm::vec2>& pts) {
    std::vector<int> xs, ys;
    float dmin = 2.0f;
    for (size_t i = 0; i < pts.size(); ++i) {
        xs.push_back(static_cast<int>(std::lround(pts[i].x * 64.0f)));
        ys.push_back(static_cast<int>(std::lround(pts[i].y * 64.0f)));
        for (size_t j = 0; j < i; ++j) {
            const glm::vec2 d = glm::abs(pts[i] - pts[j]);
            dmin = std::min(dmin, std::hypot(d.x, d.y));
        }
    }
    std::sort(xs.begin(), xs.end());
    std::sort(ys.begin(), ys.end());
    const int nx = static_cast<int>(std::unique(xs.begin(), xs.end()) - xs.begin());
    const int ny = static_cast<int>(std::unique(ys.begin(), ys.end()) - ys.begin());
    return {std::min(nx, ny), dmin};
}

class AaRuntime final : public EffectRuntime {
public:
    // The pass aa_resolve: the drawn targets' samples (and sub-frames) into the output.
    void add_resolve(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
        const FrameTargets* drawn = targets.drawn;
        if (!drawn) throw Error(ExitCode::internal, "aa_resolve: no drawn targets");
        struct Data {
            FrameGraph::ResourceId hdr = -1, depth = -1, out = -1, out_depth = -1;
        };
        const bool ms = drawn->samples > 1;
        const auto& d = graph.add_pass<Data>(
            "aa_resolve",
            [&](FrameGraph::Builder& b, Data& data) {
                data.hdr = b.read(drawn->hdr, AA_HDR_UNIT);
                data.depth = b.read(drawn->depth, AA_DEPTH_UNIT);
                data.out = b.write(targets.hdr);
                data.out_depth = b.create("depth_resolved", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            },
            [&env, ms](const Data& data, FrameGraph::Context& ctx) {
                // Sub-frame k of n: out = out + (resolved - out) / (k + 1), the running mean.
                gl::PipelineState ps;
                ps.depth_test = true;
                ps.depth_func = GL_ALWAYS;
                ps.depth_write = true;
                if (env.subframe > 0) {
                    ps.blend = true;
                    ps.blend_src_rgb = ps.blend_src_alpha = GL_CONSTANT_ALPHA;
                    ps.blend_dst_rgb = ps.blend_dst_alpha = GL_ONE_MINUS_CONSTANT_ALPHA;
                    glBlendColor(0.0f, 0.0f, 0.0f, 1.0f / static_cast<float>(env.subframe + 1));
                }
                ctx.state.apply(ps);
                ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(data.out)}, &ctx.texture(data.out_depth)));
                ctx.state.viewport(0, 0, env.width, env.height);
                const GLuint program = env.programs.get(ms ? "aa_resolve" : "aa_resolve_single").id();
                ctx.state.use_program(program);
                ctx.state.bind_vertex_array(env.empty_vao.id());
                glDrawArrays(GL_TRIANGLES, 0, 3);
                ++ctx.counters.draw_calls;
                ctx.counters.triangles += 1;
                // The pool may attach these textures to framebuffers next: leave no unit on them.
                glBindTextureUnit(AA_HDR_UNIT, 0);
                glBindTextureUnit(AA_DEPTH_UNIT, 0);
            });
        (void)d;
        targets.depth = d.out_depth;
    }
};

class Aa final : public Effect {
public:
    const char* name() const override { return "aa"; }
    bool switchable() const override { return false; }
    std::any default_options() const override { return AaOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<AaOptions>("aa", [](RenderSettings& s) -> AaOptions& { return s.get<AaOptions>(); })
            .choice("mode", &AaOptions::mode, kAaModes,
                    "anti-aliasing: msaa multisamples (forward: every sample covered, shaded once; deferred: edge pixels shaded per sample)")
            .choice("samples", &AaOptions::samples, kAaSampleCounts,
                    "samples per pixel (given alone, more than 1 sets aa.mode=msaa); counts the device cannot multisample are made "
                    "of sub-frames (projection shifted per sub-frame)")
            .boolean("alpha_to_coverage", &AaOptions::alpha_to_coverage,
                     "forward with msaa: MASK materials cover samples in proportion to their alpha near the cutoff")
            .boolean("specular_filter", &AaOptions::specular_filter,
                     "with msaa: the specular lobe widened by the normal's turn over the pixel (NDF filtering), so that a "
                     "highlight smaller than a pixel gives the pixel's mean instead of what a few samples hit")
            .rows;
    }
    // Asking for samples is asking for multisampling, unless aa.mode is given too.
    void complete_knobs(RenderSettings& s, const std::set<std::string>& given) const override {
        if (given.count("aa.samples") && !given.count("aa.mode") && static_cast<int>(s.get<AaOptions>().samples) > 1)
            s.get<AaOptions>().mode = AaMode::msaa;
    }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        const AaOptions& o = s.get<AaOptions>();
        const int n = static_cast<int>(o.samples);
        // Switched by its own knobs, not by the scene: off is "not enabled" (render.gating=off does
        // not force it on), like an effect switched off with --effects.
        if (o.mode == AaMode::off || n <= 1) {
            EffectDecision d = decide_effect(name(), false, true, "", true);
            d.reason = o.mode == AaMode::off ? "off: aa.mode=off" : "off: aa.samples=1";
            return d;
        }
        if (f.decision("transparency").planned && s.get<TransparencyOptions>().mode == TransparencyMode::peeling)
            return decide_effect(name(), true, false, "transparency.mode=peeling peels single-sample layers (use sorted with msaa)", true);
        if (s.debug.view != DebugView::none)
            return decide_effect(name(), true, false, "a debug view shows a buffer, not radiance", true);
        return decide_effect(name(), true, true, std::to_string(n) + " samples per pixel (aa.mode=msaa)", true);
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        if (stage != Stage::post) return;
        const AaPlan p = aa_plan(f, s);
        PlannedPass resolve{"aa_resolve",
                            std::to_string(p.samples) + " samples: " + std::to_string(p.device_samples) + " multisampled x " +
                                std::to_string(p.subframes) + " sub-frame(s)",
                            this,
                            {p.device_samples > 1 ? "aa_resolve" : "aa_resolve_single"}};
        resolve.every_subframe = true;  // the running mean of the sub-frames
        resolve.work = runtime_pass<AaRuntime>([](AaRuntime& r, const PassSite& p) { r.add_resolve(p.graph, p.env, p.targets); });
        out.push_back(std::move(resolve));
    }
    // The drawing targets are the resolve's: multisampled with the device's samples, and with
    // counts the device cannot multisample, sub-frames with shifted projections (aa.hpp).
    void frame_sampling(const Features& f, const RenderSettings& s, FrameSampling& out) const override {
        const AaPlan p = aa_plan(f, s);
        out.resolved = p.on;
        out.samples = p.device_samples;
        out.positions = device_sample_positions(p.device_samples);
        out.subframes = p.subframes;
        out.offsets = p.offsets;
        // MASK materials' coverage from their alpha (forward.frag, gbuffer.frag: u_alpha_to_coverage).
        out.coverage = s.get<AaOptions>().alpha_to_coverage;
        // The pixel filter's variance as Tokuyoshi and Kaplanyan (2021, JCGT 10(2)) take it:
        // 1/(2 pi) pixel^2, the Gaussian with the unit box's peak. (The box's own second moment,
        // 1/12, does better on AaTest's sub-pixel highlight and worse on the random scenes'
        // highlights: docs/effects/aa.md.)
        if (p.on && s.get<AaOptions>().specular_filter) out.specular_filter_variance = 0.15915494f;
    }
    // The plan takes the device's sample counts.
    bool plans_with_device(const RenderSettings& s) const override { return s.get<AaOptions>().mode != AaMode::off; }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"aa_resolve", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/aa/resolve.frag"}}, {"MULTISAMPLED"}},
                {"aa_resolve_single", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/aa/resolve.frag"}}, {}}};
    }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<AaRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return aa_accuracy_sweeps(quick); }
};

}  // namespace

const std::vector<int>& device_sample_counts() {
    static std::vector<int> counts;
    static const std::vector<int> single = {1};
    if (!counts.empty()) return counts;
    // No GL context (yet), or none current: the planner assumes single samples (not cached).
    if (!glad_glGetInternalformativ || !glad_glGetString || !glGetString(GL_VERSION)) return single;
    std::vector<int> common;
    bool first = true;
    for (GLenum format : {GL_RGBA32F, GL_RGBA16F, GL_RG16F, GL_RGBA8, GL_DEPTH_COMPONENT32F}) {
        GLint n = 0;
        glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, format, GL_NUM_SAMPLE_COUNTS, 1, &n);
        std::vector<GLint> v(static_cast<size_t>(std::max(n, 0)));
        if (n > 0) glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, format, GL_SAMPLES, n, v.data());
        std::vector<int> these(v.begin(), v.end());
        if (first) common = these;
        else {
            std::vector<int> both;
            for (int c : common)
                if (std::find(these.begin(), these.end(), c) != these.end()) both.push_back(c);
            common = both;
        }
        first = false;
    }
    counts = {1};
    for (int c : common)
        if (c > 1 && c <= 8) counts.push_back(c);
    std::sort(counts.begin(), counts.end());
    return counts;
}

namespace {
std::vector<glm::vec2> query_sample_positions(int n) {
    std::vector<glm::vec2> out;
    if (n <= 1) return {glm::vec2(0.0f)};
    GLuint fbo = 0, tex = 0;
    glCreateFramebuffers(1, &fbo);
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &tex);
    glTextureStorage2DMultisample(tex, n, GL_RGBA8, 4, 4, GL_TRUE);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    GLint previous = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    for (int i = 0; i < n; ++i) {
        GLfloat p[2] = {0.5f, 0.5f};
        glGetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(i), p);
        out.emplace_back(p[0] - 0.5f, p[1] - 0.5f);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous));
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
    return out;
}
}  // namespace

const std::vector<glm::vec2>& device_sample_positions(int n) {
    static std::vector<glm::vec2> cache[9];
    const size_t i = static_cast<size_t>(std::clamp(n, 1, 8));
    if (cache[i].empty()) cache[i] = query_sample_positions(static_cast<int>(i));
    return cache[i];
}

AaPlan aa_plan_for(int samples, const std::vector<int>& counts, const std::vector<glm::vec2>& positions) {
    AaPlan p;
    p.on = samples > 1;
    p.samples = std::max(1, samples);
    for (int c : counts)
        if (c <= p.samples && p.samples % c == 0) p.device_samples = std::max(p.device_samples, c);
    p.subframes = p.samples / p.device_samples;
    if (p.subframes == 1) return p;
    if (p.device_samples == 1) {
        p.offsets = rook_pattern(p.subframes);
        return p;
    }
    // Every sample must stay inside its pixel (a box filter, not a wider one): the shifts are
    // bounded by the device pattern's margin to the pixel's border.
    float reach = 0.0f;
    for (glm::vec2 q : positions) reach = std::max({reach, std::abs(q.x), std::abs(q.y)});
    const float room = 0.5f - reach - 1.0f / 128.0f;
    if (p.subframes == 2) {
        // Two sub-frames at +h and -h: the h (1/64 pixel grid) whose union has the most distinct
        // columns and rows, then the largest smallest distance.
        std::pair<int, float> best{-1, -1.0f};
        glm::vec2 best_h(0.0f);
        for (int a = -16; a <= 16; ++a)
            for (int b = -16; b <= 16; ++b) {
                const glm::vec2 h(static_cast<float>(a) / 64.0f, static_cast<float>(b) / 64.0f);
                if (std::abs(h.x) > room || std::abs(h.y) > room) continue;
                std::vector<glm::vec2> u;
                for (glm::vec2 q : positions) {
                    u.push_back(q + h + 0.5f);
                    u.push_back(q - h + 0.5f);
                }
                const auto sc = pattern_score(u);
                if (sc > best) {
                    best = sc;
                    best_h = h;
                }
            }
        p.offsets = {best_h, -best_h};
        return p;
    }
    // More sub-frames: the rook pattern of that count, scaled into the room left.
    p.offsets.clear();
    for (glm::vec2 o : rook_pattern(p.subframes)) p.offsets.push_back(o * (std::max(room, 0.0f) / (7.0f / 16.0f)));
    return p;
}

AaPlan aa_plan(const Features& f, const RenderSettings& s) {
    if (!f.decision("aa").planned) return AaPlan{};
    const std::vector<int>& counts = device_sample_counts();
    const int n = static_cast<int>(s.get<AaOptions>().samples);
    int hw = 1;
    for (int c : counts)
        if (c <= n && n % c == 0) hw = std::max(hw, c);
    return aa_plan_for(n, counts, device_sample_positions(hw));
}

const Effect& aa_effect() {
    static const Aa effect;
    return effect;
}

}  // namespace candela
