#include "render/passes/pass_env.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <string>

#include "core/error.hpp"
#include "effects/area_lights/area_lights_data.h"
#include "effects/effect.hpp"
#include "effects/gi/gi_data.h"
#include "effects/reflections/reflections_data.h"
#include "effects/rsm/rsm_data.h"
#include "effects/shadows/shadows_data.h"
#include "gpu/bindings.h"

namespace candela {

GLuint FramebufferCache::get(const std::vector<const gl::Texture*>& colors, const gl::Texture* depth) {
    std::vector<GLuint> key;
    for (const auto* c : colors) key.push_back(c->id());
    key.push_back(depth ? depth->id() : 0);
    auto it = fbos_.find(key);
    if (it != fbos_.end()) return it->second.id();
    gl::Framebuffer fbo = gl::Framebuffer::create();
    std::vector<GLenum> buffers;
    for (size_t i = 0; i < colors.size(); ++i) {
        fbo.attach(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), *colors[i]);
        buffers.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
    }
    glNamedFramebufferDrawBuffers(fbo.id(), static_cast<GLsizei>(buffers.size()), buffers.empty() ? nullptr : buffers.data());
    if (buffers.empty()) glNamedFramebufferDrawBuffer(fbo.id(), GL_NONE);
    if (depth) fbo.attach(GL_DEPTH_ATTACHMENT, *depth);
    fbo.check_complete("frame graph pass");
    const GLuint id = fbo.id();
    fbos_.emplace(std::move(key), std::move(fbo));
    return id;
}

void draw_fullscreen(const PassEnv& env, FrameGraph::Context& ctx, GLuint fbo, int w, int h, GLuint program) {
    ctx.state.apply(gl::PipelineState{});
    ctx.state.bind_framebuffer(fbo);
    ctx.state.viewport(0, 0, w, h);
    ctx.state.use_program(program);
    ctx.state.bind_vertex_array(env.empty_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    ++ctx.counters.draw_calls;
    ctx.counters.triangles += 1;
}

void bind_scene_buffers(const PassEnv& env) {
    glBindBufferBase(GL_UNIFORM_BUFFER, FRAME_BINDING, env.frame_ubo.id());
    for (const EffectRuntime* e : env.effects) e->bind_shading_inputs(env, nullptr);  // their blocks
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MATERIALS_BINDING, env.scene.materials().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, LIGHTS_BINDING, env.scene.lights().id());
    glBindTextureUnit(ENVIRONMENT_UNIT, env.scene.environment_map().id());
    glBindSampler(ENVIRONMENT_UNIT, 0);
    if (env.env_cube) {
        glBindTextureUnit(ENV_CUBE_UNIT, env.env_cube.id());
        glBindSampler(ENV_CUBE_UNIT, 0);
    }
    glBindTextureUnit(BRDF_LUT_UNIT, env.ibl.brdf_lut().id());
    glBindSampler(BRDF_LUT_UNIT, 0);
}

void read_lighting_inputs(FrameGraph::Builder& b, const PassEnv& env) {
    for (const EffectRuntime* e : env.effects) e->read_shading_inputs(b);
}

void bind_effect_inputs(const PassEnv& env, FrameGraph::Context& ctx) {
    for (const EffectRuntime* e : env.effects) e->bind_shading_inputs(env, &ctx);
}

void begin_forward_shading(const PassEnv& env, FrameGraph::Context& ctx, const FrameTargets& targets,
                           const gl::PipelineState& ps) {
    ctx.state.apply(ps);
    ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.hdr)}, &ctx.texture(targets.depth)));
    ctx.state.viewport(0, 0, env.width, env.height);
    bind_scene_buffers(env);
    bind_effect_inputs(env, ctx);
    ctx.state.use_program(env.programs.get("forward").id());
}

namespace {
// The contents of the uniform block bound at `binding` (what the shaders will read), or false
// when none is bound.
template <class Block>
bool read_bound_block(GLuint binding, Block& out) {
    GLint buffer = 0;
    GLint64 start = 0, size = 0;
    glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, binding, &buffer);
    glGetInteger64i_v(GL_UNIFORM_BUFFER_START, binding, &start);
    glGetInteger64i_v(GL_UNIFORM_BUFFER_SIZE, binding, &size);
    if (buffer == 0) return false;
    GLint64 buffer_size = 0;
    glGetNamedBufferParameteri64v(static_cast<GLuint>(buffer), GL_BUFFER_SIZE, &buffer_size);
    if (start < 0 || start + static_cast<GLint64>(sizeof(Block)) > buffer_size || (size > 0 && size < static_cast<GLint64>(sizeof(Block))))
        return false;
    glGetNamedBufferSubData(static_cast<GLuint>(buffer), static_cast<GLintptr>(start), sizeof(Block), &out);
    return true;
}

// True when no material in the materials SSBO has a texture in any slot (material_uv.glsl sets
// a slot's bit from its texcoord set, -1 for none).
bool no_material_textures(const GpuScene& scene) {
    GLint64 bytes = 0;
    glGetNamedBufferParameteri64v(scene.materials().id(), GL_BUFFER_SIZE, &bytes);
    const size_t count = static_cast<size_t>(bytes) / sizeof(MaterialData);
    if (count == 0) return false;
    std::vector<MaterialData> materials(count);
    glGetNamedBufferSubData(scene.materials().id(), 0, static_cast<GLsizeiptr>(count * sizeof(MaterialData)), materials.data());
    for (const MaterialData& m : materials)
        if (m.texcoord.x >= 0 || m.texcoord.y >= 0 || m.texcoord.z >= 0 || m.texcoord.w >= 0 || m.emissive_texcoord >= 0) return false;
    return true;
}
}  // namespace

// The defines both lighting programs (forward.frag, deferred/light.comp) take from the bound
// blocks: each removes code whose runtime condition is known false from the values the shaders
// will read. llvmpipe runs both sides of a branch under a lane mask, so dead features cost per
// pixel, not only at compile time.
static std::string lighting_defines(const PassEnv& env, std::string defines) {
    auto add = [&defines](const std::string& d) { defines += (defines.empty() ? "" : ",") + d; };
    if (env.frame.debug_view == 0) add("FORWARD_NO_DEBUG");
    gpu::ReflectionsData reflections{};
    if (read_bound_block(REFLECTIONS_BINDING, reflections)) {
        if (reflections.refraction == 0) add("FORWARD_NO_REFRACTION");
        if (reflections.probes <= 0) add("FORWARD_NO_PROBES");
    }
    gpu::AreaLightsData area{};
    if (read_bound_block(AREA_LIGHTS_BINDING, area) && (area.method != 1 || area.polygon_count <= 0)) add("FORWARD_NO_AREA_LIGHTS");
    gpu::RsmData rsm{};
    if (read_bound_block(RSM_BINDING, rsm) && rsm.on == 0) add("FORWARD_NO_RSM");
    gpu::GiData gi{};
    if (read_bound_block(GI_BINDING, gi) && gi.on < 0.5f) add("FORWARD_NO_GI");
    // The shadow filter (shadows_shading.glsl): only the selected mode's code is compiled.
    gpu::ShadowsData shadows{};
    if (read_bound_block(SHADOWS_BINDING, shadows) && shadows.filter_mode >= 0 && shadows.filter_mode <= 3)
        add("SHADOW_FILTER_MODE " + std::to_string(shadows.filter_mode));
    return defines;
}

std::string forward_program_name(const PassEnv& env, bool may_peel) {
    std::string defines;
    if (!may_peel) defines = "FORWARD_NO_PEEL";
    if (no_material_textures(env.scene)) defines += (defines.empty() ? "" : ",") + std::string("FORWARD_NO_TEXTURES");
    defines = lighting_defines(env, defines);
    return defines.empty() ? "forward" : "forward#" + defines;
}

std::string deferred_light_program_name(const PassEnv& env, const std::string& base) {
    const std::string defines = lighting_defines(env, "");
    return defines.empty() ? base : base + "#" + defines;
}

void draw_item(const PassEnv& env, FrameGraph::Context& ctx, const GpuScene::Draw& d, bool cull, GLenum cull_face,
               GLuint program_id, bool depth_only) {
    ctx.state.set_cull(cull, cull_face);
    // A mirroring transform reverses the winding of its triangles.
    ctx.state.set_front_face(d.mirrored ? GL_CW : GL_CCW);
    const GLuint program = program_id ? program_id : env.programs.get("forward").id();
    glProgramUniformMatrix4fv(program, 0, 1, GL_FALSE, glm::value_ptr(d.model));
    if (!depth_only) glProgramUniformMatrix3fv(program, 1, 1, GL_FALSE, glm::value_ptr(d.normal_matrix));
    glProgramUniform1i(program, 2, d.primitive_material);
    if (!depth_only) glProgramUniform1i(program, 3, d.mirrored ? 1 : 0);
    for (int s = 0; s < (depth_only ? 1 : MATERIAL_UNIT_COUNT); ++s) {
        const auto su = static_cast<size_t>(s);
        const gl::Texture& t = d.textures[su] >= 0 ? env.scene.texture(d.textures[su], d.srgb[su]) : env.scene.white_texture();
        glBindTextureUnit(static_cast<GLuint>(BASE_COLOR_UNIT + s), t.id());
        glBindSampler(static_cast<GLuint>(BASE_COLOR_UNIT + s), env.scene.sampler(d.samplers[su]).id());
    }
    glDrawElementsBaseVertex(GL_TRIANGLES, d.index_count, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(d.first_index * sizeof(std::uint32_t)), d.base_vertex);
    ++ctx.counters.draw_calls;
    ctx.counters.triangles += static_cast<std::size_t>(d.index_count / 3);
}

}  // namespace candela
