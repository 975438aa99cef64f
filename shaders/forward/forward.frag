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
#ifdef TILED_LIGHTS
// Per 16x16 tile, the lights that can reach it as bit sets (forward/light_tiles.comp).
layout(std430, binding = LIGHT_TILES_BINDING) readonly buffer LightTiles { uint tile_masks[]; };
#endif

// Specialisation (render/passes/pass_env.hpp, forward_program_name): defines leave out the code
// of a feature whose uniforms say it is off this frame, so that the image is the same: llvmpipe
// executes both sides of a branch under a lane mask, so dead features cost per pixel.
// NO_PEELING (u_peel is 0), NO_DEBUG_VIEW (frame.debug_view is 0), NO_MATERIAL_TEXTURES (no
// material has a texture: lighting/surface.glsl); each effect's defines do the same inside its
// shading include (EffectRuntime::shading_defines). TILED_LIGHTS: the lights were culled per tile.
#ifdef NO_PEELING
#define PEELING false
#else
#define PEELING (u_peel != 0)
#endif

void main() {
#ifndef NO_PEELING
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
#ifndef NO_DEBUG_VIEW
    if (frame.debug_view == DEBUG_VIEW_INDIRECT) {
        vec3 indirect = vec3(0.0);
        effect_add_indirect_light(indirect, s.brdf, s.p, s.n, v, pixel, s.occlusion, 0.0);
        out_radiance = vec4(indirect, 1.0);
        return;
    }
    if (frame.debug_view != DEBUG_VIEW_NONE) {
        float value = frame.debug_view == DEBUG_VIEW_VISIBILITY ? light_visibility(s.p, s.n, pixel) : effect_occlusion(pixel);
        out_radiance = vec4(vec3(value), 1.0);
        return;
    }
#endif
#ifdef MATERIAL_LAYERS
    if (s.unlit) {
        float a = s.alpha_mode == 2 || (s.alpha_mode == 1 && g_alpha_to_coverage) ? s.alpha : 1.0;
        if (effect_capture_view()) a = 0.0;  // no emitter the direct-light hook adds (see the end of main)
        out_radiance = PEELING ? vec4(s.brdf.base_color * a, a) : vec4(s.brdf.base_color, a);
        return;
    }
#endif
    vec3 color = s.emission;
    // Transmission needs a refraction source (effect_refraction); without one the surface is an
    // opaque dielectric.
    float transmission = effect_refraction() ? s.transmission : 0.0;
    if (transmission > 0.0 && !s.thin) {
        MaterialData mat = materials[u_material];
        if (mat.attenuation_distance > 0.0)
            g_volume_sigma = -log(max(mat.attenuation_color, vec3(1e-6))) / mat.attenuation_distance;
    }
#ifdef TILED_LIGHTS
    // The lights that can reach this 16x16 tile (light_tiles.comp), in index order: the sum of
    // the loop below without the lights that add exactly nothing here.
    {
        int count = effect_shaded_light_count();
        int words = (frame.light_count + 31) / 32;
        ivec2 tile = ivec2(gl_FragCoord.xy) / 16;
        int base = (tile.y * ((int(frame.viewport.x) + 15) / 16) + tile.x) * words;
        for (int w = 0; w < (count + 31) / 32; ++w) {
            uint bits = tile_masks[base + w];
            while (bits != 0u) {
                int b = findLSB(bits);
                bits &= bits - 1u;
                int i = w * 32 + b;
                if (i < count) color += shade_light(i, s.brdf, s.p, s.n, v, pixel, transmission);
            }
        }
    }
#else
    for (int i = 0; i < effect_shaded_light_count(); ++i) color += shade_light(i, s.brdf, s.p, s.n, v, pixel, transmission);
#endif
    effect_add_direct_light(color, s.brdf, s.p, s.n, v, pixel, transmission);
    color += shade_ambient(s.brdf, s.p, s.n, v, s.occlusion * effect_occlusion(pixel), transmission, s.thin);
    effect_add_indirect_light(color, s.brdf, s.p, s.n, v, pixel, s.occlusion, transmission);
    // In a capture view the alpha channel carries the luminance of the emission that the
    // direct-light hook adds analytically (every emissive surface is an emitter when the light
    // buffer holds area-light pieces), so that a reflection read from the capture can leave it
    // out (effect_reflection_radiance): counted once, by the emitter, which also shadows it.
    if (effect_capture_view()) {
        out_radiance = vec4(color, frame.light_count > frame.punctual_light_count ? dot(s.emission, LUMINANCE_WEIGHTS) : 0.0);
        return;
    }
    float alpha = s.alpha_mode == 2 || (s.alpha_mode == 1 && g_alpha_to_coverage) ? s.alpha : 1.0;
    out_radiance = PEELING ? vec4(color * alpha, alpha) : vec4(color, alpha);
}
