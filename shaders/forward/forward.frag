#version 450 core
// Forward PBR shading: every light per pixel (with its shadow), emission, environment ambient.
#include "../common/scene_data.glsl"
#include "../lighting/surface.glsl"
#include "../lighting/shading.glsl"

layout(location = 0) out vec4 out_radiance;

// Depth peeling (transparency.mode=peeling): 1 the first layer, 2 a later one; 0 otherwise. A
// peeled fragment must lie in front of the opaque depth and behind the previous layer, and is
// written premultiplied for front-to-back compositing (Everitt 2001; Bavoil & Myers 2008).
layout(location = 8) uniform int u_peel;
layout(binding = OPAQUE_DEPTH_UNIT) uniform sampler2D t_opaque_depth;
layout(binding = PREVIOUS_LAYER_UNIT) uniform sampler2D t_previous_layer;
// 1: MASK materials output their coverage alpha (surface.glsl) with GL_SAMPLE_ALPHA_TO_COVERAGE on.
layout(location = 9) uniform int u_alpha_to_coverage;

// Specialisation (render/passes/pass_env.hpp, forward_program_name): FORWARD_NO_* leave out the
// code of a feature whose uniforms say it is off this frame, so that the image is the same:
// llvmpipe executes both sides of a branch under a lane mask, so dead features cost per pixel.
// FORWARD_NO_PEEL (u_peel is 0), FORWARD_NO_DEBUG (frame.debug_view is 0), FORWARD_NO_REFRACTION
// (reflections.refraction 0), FORWARD_NO_PROBES (reflections.probes 0), FORWARD_NO_AREA_LIGHTS,
// FORWARD_NO_RSM (rsm.on 0), FORWARD_NO_GI (gi.on < 0.5), FORWARD_NO_TEXTURES (no
// material has a texture: lighting/surface.glsl).
#ifdef FORWARD_NO_PEEL
#define PEELING false
#else
#define PEELING (u_peel != 0)
#endif

void main() {
#ifndef FORWARD_NO_PEEL
    if (u_peel != 0) {
        ivec2 px = ivec2(gl_FragCoord.xy);
        // Reversed-Z: a larger depth is nearer.
        if (gl_FragCoord.z <= texelFetch(t_opaque_depth, px, 0).r) discard;
        if (u_peel == 2 && gl_FragCoord.z >= texelFetch(t_previous_layer, px, 0).r) discard;
    }
#endif
    g_alpha_to_coverage = u_alpha_to_coverage != 0;
    Surface s = fragment_surface();
    vec3 v = normalize(frame.camera_pos.xyz - s.p);
    vec2 pixel = gl_FragCoord.xy;
#ifndef FORWARD_NO_DEBUG
    if (frame.debug_view == 3) {
        out_radiance = vec4(rsm_indirect(s.brdf, pixel, s.p) + shade_gi(s.brdf, s.p, s.n, v, s.occlusion, 0.0), 1.0);
        return;
    }
    if (frame.debug_view != 0) {
        float value = frame.debug_view == 1 ? light_visibility(s.p, s.n, pixel) : ssao_at(pixel);
        out_radiance = vec4(vec3(value), 1.0);
        return;
    }
#endif
#ifdef MATERIAL_LAYERS
    if (s.unlit) {
        float a = s.alpha_mode == 2 || (s.alpha_mode == 1 && g_alpha_to_coverage) ? s.alpha : 1.0;
        if (reflections.capture != 0) a = 0.0;  // no area light (see the end of main)
        out_radiance = PEELING ? vec4(s.brdf.base_color * a, a) : vec4(s.brdf.base_color, a);
        return;
    }
#endif
    vec3 color = s.emission;
    // Transmission needs the refraction lookup (reflections effect); without it the surface is
    // an opaque dielectric.
#ifdef FORWARD_NO_REFRACTION
    float transmission = 0.0;
#else
    float transmission = reflections.refraction != 0 ? s.transmission : 0.0;
    if (transmission > 0.0 && !s.thin) {
        MaterialData mat = materials[u_material];
        if (mat.attenuation_distance > 0.0)
            g_volume_sigma = -log(max(mat.attenuation_color, vec3(1e-6))) / mat.attenuation_distance;
    }
#endif
    for (int i = 0; i < shaded_light_count(); ++i) color += shade_light(i, s.brdf, s.p, s.n, v, pixel, transmission);
#ifndef FORWARD_NO_AREA_LIGHTS
    color += shade_area_lights(s.brdf, s.p, s.n, v, pixel, transmission);
#endif
    color += shade_ambient(s.brdf, s.p, s.n, v, s.occlusion * ssao_at(pixel), transmission, s.thin);
#ifndef FORWARD_NO_RSM
    color += rsm_indirect(s.brdf, pixel, s.p);
#endif
#ifndef FORWARD_NO_GI
    color += shade_gi(s.brdf, s.p, s.n, v, s.occlusion, transmission);
#endif
    // Inside a reflection probe's capture the alpha channel carries the luminance of the emission
    // that the area lights add analytically (every emissive surface is one when the light buffer
    // holds area-light pieces), so that a reflection read from the probe can leave it out
    // (probe_radiance): counted once, by the area lights, which also shadow it.
    if (reflections.capture != 0) {
        out_radiance = vec4(color, frame.light_count > frame.punctual_light_count ? dot(s.emission, LUMINANCE_WEIGHTS) : 0.0);
        return;
    }
    float alpha = s.alpha_mode == 2 || (s.alpha_mode == 1 && g_alpha_to_coverage) ? s.alpha : 1.0;
    out_radiance = PEELING ? vec4(color * alpha, alpha) : vec4(color, alpha);
}
