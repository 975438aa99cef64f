#version 450 core
// G-buffer pass of the deferred path: the surface of every opaque and masked fragment, and its
// emission straight into the light buffer. Layout: lighting/gbuffer.glsl.
#include "../common/scene_data.glsl"
#include "../lighting/surface.glsl"
#include "../lighting/gbuffer.glsl"

layout(location = 0) out vec4 out_base_occlusion;
layout(location = 1) out vec4 out_normal_rm;
layout(location = 2) out vec4 out_f0_f90;
layout(location = 3) out vec4 out_emission;
// 1: a multisampled G-buffer with aa.alpha_to_coverage. A MASK fragment covers round(alpha x N)
// of its samples (alpha: surface.glsl's coverage alpha around the cutoff), written through
// gl_SampleMask rather than GL_SAMPLE_ALPHA_TO_COVERAGE, whose alpha would be output 0's, the
// occlusion here.
layout(location = 9) uniform int u_alpha_to_coverage;

void main() {
    g_alpha_to_coverage = u_alpha_to_coverage != 0;
    Surface s = fragment_surface();
    gl_SampleMask[0] = -1;  // a shader that writes the mask anywhere must write it always
    if (g_alpha_to_coverage && s.alpha_mode == 1) {
        int k = clamp(int(s.alpha * float(gl_NumSamples) + 0.5), 0, gl_NumSamples);
        if (k == 0) discard;
        // Which samples: rotated by the pixel, so that neighbouring pixels of one coverage do
        // not all keep the same corner of the pixel.
        int r = (int(gl_FragCoord.x) + 2 * int(gl_FragCoord.y)) % gl_NumSamples;
        int bits = (1 << k) - 1;
        int full = (1 << gl_NumSamples) - 1;
        gl_SampleMask[0] = ((bits << r) | (bits >> (gl_NumSamples - r))) & full;
    }
#ifdef MATERIAL_LAYERS
    // Unlit: no surface for the lights (black, no specular), its colour as emission. The other
    // layers do not fit the G-buffer; the deferred path shades their base only.
    if (s.unlit) {
        s.emission = s.brdf.base_color;
        s.brdf.base_color = vec3(0.0);
        s.brdf.specular_factor = 0.0;
        s.brdf.metallic = 0.0;
    }
#endif
    out_base_occlusion = vec4(gbuffer_encode_srgb(s.brdf.base_color), s.occlusion);
    out_normal_rm = vec4(oct_encode(s.n), s.brdf.roughness, s.brdf.metallic);
    out_f0_f90 = vec4(dielectric_f0(s.brdf), dielectric_f90(s.brdf));
    out_emission = vec4(s.emission, 1.0);
}
