// The viewer's reference mode (the ray tracer refines the current view between frames, shown
// beside, over or against the raster) and the texture inspector.
#include "viewer_internal.hpp"

#include "gpu/bindings.h"
#include "rt/tracer_options.hpp"
#include "render/program_catalog.hpp"

namespace candela::viewer {
namespace {

// An RGBA8 texture holding display values (top row first in `img`, [0,1]).
void upload_display(gl::Texture& tex, const ImageF& img) {
    if (!tex || tex.width() != img.width || tex.height() != img.height) tex = gl::Texture::create_2d(GL_RGBA8, img.width, img.height, 1);
    std::vector<unsigned char> bytes(static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 4);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.at(x, img.height - 1 - y);  // GL's first row is the bottom one
            unsigned char* o = bytes.data() + (static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)) * 4;
            for (int c = 0; c < 3; ++c) o[c] = static_cast<unsigned char>(std::clamp(p[c], 0.0f, 1.0f) * 255.0f + 0.5f);
            o[3] = 255;
        }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(tex.id(), 0, 0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
}

}  // namespace

void Viewer::update_reference(const Camera& camera, int w, int h) {
    Reference& r = ref_;
    if (!r.on) return;
    // Motion blur in the reference: the shutter is open and something is animated. The tracer
    // then poses the scene itself per time slice (Options::pose_at) and rebuilds on restart.
    const bool motion = anim_.animation >= 0 && !shutter_.instant();
    if (!r.tracer || r.built_mode != r.mode || r.built_motion != motion) {
        rt::Options o = rt::tracer_options(settings_);
        o.mode = *rt::parse_mode(Reference::kModes[r.mode]);
        o.spp = 1 << 16;
        o.tile_rows = 16;
        if (motion) {
            // A time per sample (rt.shutter_slices is for `render`: with N slices over the
            // reference's 65536 samples its first slice would last 65536 / N samples).
            o.pose_at = [this](float u) { pose_within_shutter(u); };
            o.shutter_slices = 0;
        }
        try {
            r.tracer = std::make_unique<rt::RayTracer>(shaders_, scene_, gpu_, o);
        } catch (const Error& e) {
            settings_error_ = e.what();
            r.on = false;
            return;
        }
        r.built_mode = r.mode;
        r.built_motion = motion;
        r.pose_serial = pose_serial_;  // made from the scene as it is posed now
        if (motion) {
            char line[200];
            std::snprintf(line, sizeof line, "viewer: reference: motion blur, the tracer poses the scene over the shutter %.4f..%.4f s (a time per sample)",
                          shutter_.open, shutter_.close);
            log::info(line);
        }
        r.width = 0;  // restart below
    }
    if (r.pose_serial != pose_serial_) {
        // The pose changed: the accumulation starts over on the new geometry. With motion the
        // restart rebuilds at the frame's time itself; without, the tree is rebuilt here (a
        // refit would degrade over a long playback; a rebuild on Fox is well under a millisecond).
        if (!motion) r.tracer->update_geometry(rt::RtUpdate::rebuild);
        r.pose_serial = pose_serial_;
        r.width = 0;
        if (!anim_.playing) {  // a scrub or a new animation (while playing this is every frame)
            char line[160];
            std::snprintf(line, sizeof line, "viewer: reference restarts: new pose at %.3f s%s", anim_.time,
                          motion ? ", motion blur over the shutter" : "");
            log::info(std::string(line) + (motion ? " " + std::to_string(shutter_.open) + ".." + std::to_string(shutter_.close) + " s" : ""));
        }
    }
    const Camera lensed = with_lens(camera, settings_);  // camera.aperture / camera.focus_distance
    if (camera.world != r.camera || glm::vec2(lensed.aperture, lensed.focus_distance) != r.lens || w != r.width || h != r.height) {
        r.motion_slices = 0;  // the shutter times start over (pose_within_shutter)
        r.tracer->progressive_restart(lensed, w, h);
        r.camera = camera.world;
        r.lens = glm::vec2(lensed.aperture, lensed.focus_distance);
        r.width = w;
        r.height = h;
        r.shown_samples = -1;
    }
    r.tracer->progressive_step(r.budget_ms);
    // Read back when a whole sample more is in (a readback costs as much as a few tiles), and
    // every frame while the first sample is still coming in (its rows appear as they finish).
    const int samples = r.tracer->progressive_samples();
    if (samples == r.shown_samples && samples > 0) return;
    r.shown_samples = samples;
    const ImageF reference = r.tracer->progressive_image();
    r.nonfinite = 0;
    for (float v : reference.pixels) r.nonfinite += std::isfinite(v) ? 0 : 1;
    const ImageF raster = renderer_.read_radiance();
    const ImageF shown = to_display(reference, o_.exposure_ev);
    r.rmse = samples > 0 ? compare(raster, reference, 2.0 / 255.0).rmse : -1.0;
    r.rmse_display = samples > 0 ? compare(to_display(raster, o_.exposure_ev), shown, 2.0 / 255.0).rmse : -1.0;
    upload_display(r.image, shown);
    upload_display(r.diff, heatmap(raster, reference, 0.1));
}

void Viewer::draw_inspected(int w, int h) {
    const gl::Texture* t = renderer_.inspected();
    if (inspect_.name.empty() || !t) return;
    if (!inspect_.program) {
        ShaderLibrary::BuildResult r = shaders_.build(program_desc("debug_view"));
        if (!r.ok()) {
            shader_errors_ = r.log;
            inspect_.name.clear();
            return;
        }
        inspect_.program = std::move(r.program);
    }
    GLint target = 0;
    glGetTextureParameteriv(t->id(), GL_TEXTURE_TARGET, &target);
    const int kind = target == GL_TEXTURE_2D_ARRAY ? 1 : target == GL_TEXTURE_CUBE_MAP_ARRAY ? 2 : 0;
    const GLuint p = inspect_.program.id();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, w, h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(p);
    glProgramUniform1i(p, 0, kind);
    glProgramUniform1i(p, 1, inspect_.channel);
    glProgramUniform1f(p, 2, inspect_.scale);
    glProgramUniform1i(p, 3, inspect_.layer);
    glProgramUniform1f(p, 4, inspect_.lod);
    for (GLuint unit = DEBUG_2D_UNIT; unit <= DEBUG_CUBE_UNIT; ++unit) glBindSampler(unit, 0);
    glBindTextureUnit(static_cast<GLuint>(DEBUG_2D_UNIT + kind), t->id());  // kind 0 2D, 1 array, 2 cube
    if (!empty_vao_) empty_vao_ = gl::VertexArray::create();
    glBindVertexArray(empty_vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
}

void Viewer::draw_reference(int w, int h) {
    Reference& r = ref_;
    if (!r.on || !r.image || r.image.width() != w || r.image.height() != h || r.view == 0) return;
    if (!r.fbo) r.fbo = gl::Framebuffer::create();
    const bool flip_shows_reference = std::fmod(glfwGetTime(), 1.0) < 0.5;
    const gl::Texture& src = r.view == 4 ? r.diff : r.image;
    if (r.view == 3 && !flip_shows_reference) return;
    glNamedFramebufferTexture(r.fbo.id(), GL_COLOR_ATTACHMENT0, src.id(), 0);
    const int x0 = r.view == 2 ? w / 2 : 0;  // split: reference on the right half
    glBlitNamedFramebuffer(r.fbo.id(), 0, x0, 0, w, h, x0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

}  // namespace candela::viewer
