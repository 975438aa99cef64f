#include "render/passes/pass_env.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <string>

#include "core/error.hpp"
#include "render/effect.hpp"
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
    gl::bind_texture_unit(ENVIRONMENT_UNIT, env.scene.environment_map());
    if (env.env_cube) gl::bind_texture_unit(ENV_CUBE_UNIT, env.env_cube);
    gl::bind_texture_unit(BRDF_LUT_UNIT, env.ibl.brdf_lut());
    if (material_layers_on(env)) {
        gl::bind_texture_unit(MATERIAL_IMAGES_UNIT, env.scene.image_array());
        gl::bind_texture_unit(MATERIAL_IMAGES_SRGB_UNIT, env.scene.image_array_srgb());
    }
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

// The defines both lighting programs (forward.frag, deferred/light.comp) take: each removes code
// whose runtime condition is known false from the values the shaders will read (the frame's and,
// through EffectRuntime::shading_defines, each effect's block). llvmpipe runs both sides of a
// branch under a lane mask, so dead features cost per pixel, not only at compile time.
static std::string lighting_defines(const PassEnv& env, std::string defines) {
    auto add = [&defines](const std::string& d) { defines += (defines.empty() ? "" : ",") + d; };
    if (env.frame.debug_view == DEBUG_VIEW_NONE) add("NO_DEBUG_VIEW");
    for (const EffectRuntime* e : env.effects)
        for (const std::string& d : e->shading_defines()) add(d);
    return defines;
}

bool material_layers_on(const PassEnv& env) { return env.scene.has_material_layers() && env.settings.material_layers; }

std::string forward_program_name(const PassEnv& env, bool may_peel, bool tiled_lights) {
    std::string defines;
    if (!may_peel) defines = "NO_PEELING";
    if (tiled_lights) defines += (defines.empty() ? "" : ",") + std::string("TILED_LIGHTS");
    if (!env.scene.has_material_textures()) defines += (defines.empty() ? "" : ",") + std::string("NO_MATERIAL_TEXTURES");
    if (material_layers_on(env)) defines += (defines.empty() ? "" : ",") + std::string("MATERIAL_LAYERS");
    defines = lighting_defines(env, defines);
    return defines.empty() ? "forward" : "forward#" + defines;
}

std::string deferred_light_program_name(const PassEnv& env, const std::string& base) {
    const std::string defines = lighting_defines(env, material_layers_on(env) ? "MATERIAL_LAYERS" : "");
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
    // The solid a transmitted ray crosses (forward.frag; the programs that refract have it).
    if (!depth_only && d.solid_transmissive) {
        const GLint at = glGetUniformLocation(program, "u_volume_shape");
        if (at >= 0 && d.volume_shape == 0) {
            glProgramUniform1i(program, at, 0);
        } else if (at >= 0) {
            const glm::mat4 to_object = glm::inverse(d.model);
            glProgramUniform1i(program, at, d.volume_shape);
            glProgramUniform3fv(program, glGetUniformLocation(program, "u_volume_lo"), 1, glm::value_ptr(d.volume_lo));
            glProgramUniform3fv(program, glGetUniformLocation(program, "u_volume_hi"), 1, glm::value_ptr(d.volume_hi));
            glProgramUniformMatrix4fv(program, glGetUniformLocation(program, "u_volume_to_object"), 1, GL_FALSE, glm::value_ptr(to_object));
        }
    }
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
