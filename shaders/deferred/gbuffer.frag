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

void main() {
    Surface s = fragment_surface();
    out_base_occlusion = vec4(gbuffer_encode_srgb(s.brdf.base_color), s.occlusion);
    out_normal_rm = vec4(oct_encode(s.n), s.brdf.roughness, s.brdf.metallic);
    out_f0_f90 = vec4(dielectric_f0(s.brdf), dielectric_f90(s.brdf));
    out_emission = vec4(s.emission, 1.0);
}
