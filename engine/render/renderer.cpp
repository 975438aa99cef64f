#include "render/renderer.hpp"

#include <chrono>

#include "core/error.hpp"

namespace candela {

Renderer::Renderer(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const RenderSettings& settings)
    : scene_(scene), gpu_(gpu) {
    programs_.forward = shaders.build_or_throw({"forward", {{ShaderStage::vertex, "forward/forward.vert"},
                                                            {ShaderStage::fragment, "forward/forward.frag"}}, {}});
    programs_.sky = shaders.build_or_throw({"sky", {{ShaderStage::vertex, "forward/sky.vert"},
                                                    {ShaderStage::fragment, "forward/sky.frag"}}, {}});
    programs_.tonemap = shaders.build_or_throw({"tonemap", {{ShaderStage::vertex, "post/fullscreen.vert"},
                                                            {ShaderStage::fragment, "post/tonemap.frag"}}, {}});
    frame_ubo_ = gl::Buffer(sizeof(FrameData), nullptr, GL_DYNAMIC_STORAGE_BIT);
    empty_vao_ = gl::VertexArray::create();
    set_settings(settings);
}

void Renderer::set_settings(const RenderSettings& settings) {
    settings_ = settings;
    features_ = analyze(scene_, settings_);
    gpu_.update_lights(settings_.area.subdivisions, static_cast<std::size_t>(settings_.area.max_patches));
    features_.emissive_patches = gpu_.light_count() - features_.punctual_lights;
}

void Renderer::render(const Camera& camera, int width, int height, FrameOutput output, float exposure_ev) {
    if (width != width_ || height != height_) {
        width_ = width;
        height_ = height;
        output_ = gl::Texture::create_2d(GL_RGBA32F, width, height, 1);
        display_ = gl::Texture::create_2d(GL_RGBA8, width, height, 1);
        fbos_.clear();
        pool_.clear();
    }
    const auto t0 = std::chrono::steady_clock::now();
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    FrameData frame{};
    frame.view = glm::inverse(camera.world);
    frame.proj = projection_matrix(camera, aspect);
    frame.view_proj = frame.proj * frame.view;
    frame.inv_view_proj = glm::inverse(frame.view_proj);
    frame.camera_pos = glm::vec4(glm::vec3(camera.world[3]), 1.0f);
    frame.env_radiance = glm::vec4(gpu_.environment_radiance(), gpu_.has_environment_map() ? 1.0f : 0.0f);
    for (int i = 0; i < 9; ++i) frame.env_sh[i] = glm::vec4(gpu_.environment_sh()[static_cast<size_t>(i)], 0.0f);
    frame.counts = glm::ivec4(gpu_.light_count(), gpu_.environment_mips(), 0, 0);
    frame_ubo_.update(0, sizeof(FrameData), &frame);

    const PassEnv env{gpu_, settings_, frame, width, height, frame_ubo_, fbos_, programs_, empty_vao_};
    FrameGraph graph;
    ForwardTargets targets;
    targets.hdr = graph.import_texture("hdr", output_, {GL_RGBA32F, width, height});
    for (const PlannedPass& pass : plan_passes(features_, settings_)) {
        if (pass.name == "depth_prepass") add_depth_prepass(graph, env, targets);
        else if (pass.name == "forward_opaque") add_forward_opaque_pass(graph, env, targets, !features_.transparency.planned);
        else if (pass.name == "sky") add_sky_pass(graph, env, targets);
        else if (pass.name == "transparent") add_transparent_pass(graph, env, targets);
        else throw Error(ExitCode::internal, "renderer: no pass named '" + pass.name + "'");
    }
    // The tonemap pass is always declared; for an HDR-only frame nobody consumes its output and
    // the graph culls it.
    add_tonemap_pass(graph, env, targets, display_, exposure_ev);
    graph.mark_output(output == FrameOutput::display ? targets.display : targets.hdr);
    graph.compile(pool_);
    const double graph_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // The cache cannot know what other code did since the last frame.
    state_.reset();
    const int calls_before = state_.real_calls(), skipped_before = state_.skipped_calls();
    timer_.begin_frame();
    std::string state_problem;
    graph.execute(
        state_, [&](FrameGraph::PassRecord& p) { timer_.begin(p.name); },
        [&](FrameGraph::PassRecord& p) {
            timer_.end();
            if (verify_state_ && state_problem.empty()) {
                const std::string bad = state_.verify();
                if (!bad.empty()) state_problem = "pass '" + p.name + "' changed " + bad + " behind the state cache";
            }
        });
    graph.release(pool_);
    // Leave GL as other code (ImGui, readback) expects it.
    state_.apply(gl::PipelineState{.depth_test = false, .depth_func = GL_LESS, .reversed_z = false});
    state_.bind_framebuffer(0);

    report_ = {};
    report_.graph_ms = graph_ms;
    for (const auto& p : graph.passes()) {
        if (p.culled) report_.culled.emplace_back(p.name, p.cull_reason);
        else report_.passes.push_back({p.name, -1.0, p.cpu_ms, p.counters});
    }
    report_.pool_allocations = pool_.allocations();
    report_.pool_slots = pool_.size();
    report_.state_calls = state_.real_calls() - calls_before;
    report_.state_calls_skipped = state_.skipped_calls() - skipped_before;
    if (!state_problem.empty()) throw Error(ExitCode::internal, state_problem);
}

void Renderer::resolve_gpu_times() {
    const auto& results = timer_.resolve_current();
    for (size_t i = 0; i < report_.passes.size() && i < results.size(); ++i) report_.passes[i].gpu_ms = results[i].second;
}

std::vector<std::uint8_t> Renderer::read_display() const {
    std::vector<std::uint8_t> bytes(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 4);
    glGetTextureImage(display_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(bytes.size()), bytes.data());
    const size_t row = static_cast<size_t>(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y)
        std::swap_ranges(bytes.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * row),
                         bytes.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y + 1) * row),
                         bytes.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(height_ - 1 - y) * row));
    return bytes;
}

ImageF Renderer::read_radiance() const {
    ImageF img(width_, height_, 4);
    glGetTextureImage(output_.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(img.pixels.size() * sizeof(float)),
                      img.pixels.data());
    // GL's first row is the bottom one.
    const size_t row = static_cast<size_t>(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y)
        std::swap_ranges(img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * row),
                         img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y + 1) * row),
                         img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(height_ - 1 - y) * row));
    return img;
}

}  // namespace candela
