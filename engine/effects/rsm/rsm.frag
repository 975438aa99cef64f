#version 450 core
// Reflective shadow map (Dachsbacher & Stamminger 2005): for each texel of a light's view, the
// surface it sees - world position, normal, and the flux it reflects diffusely. A texel of
// cross-section A (perpendicular to the light) receives E * A, E the irradiance at normal
// incidence (light_incidence: intensity, spot cone, range); it reflects rho * E * A with rho the
// diffuse albedo. A = texel width^2 for orthographic views; for perspective ones the texel's solid
// angle (tangent width^2 * cos^3 of the off-axis angle) times distance^2.
// An area-light piece (radiance Le, area A) is a Lambertian emitter: E carries its cos about the
// piece's normal (light_incidence), so its texels' incident flux sums to the integral of
// Le A cos over the hemisphere, pi Le A, the piece's power (a point light's: 4 pi I).
#include "common/scene_data.glsl"
#include "lighting/surface.glsl"

layout(location = 5) uniform int u_light;
layout(location = 6) uniform vec4 u_view;  // x kind (0 ortho), y texel size (world or tangent), z flux
                                           // scale (an area light's pieces without RSM views), w unused
layout(location = 7) uniform vec3 u_axis;  // the view's forward axis (perspective)

layout(location = 0) out vec4 out_position;  // xyz world, w 1 where a surface was drawn
layout(location = 1) out vec4 out_normal;    // xyz normal facing the light
layout(location = 2) out vec4 out_flux;      // rgb reflected flux (W), a sqrt of the texel's footprint

void main() {
    Surface s = fragment_surface();
    LightData light = lights[u_light];
    vec3 l, E;
    float dist;
    light_incidence(light, v_world_pos, l, E, dist);
    vec3 n = normalize(v_normal);
    if (dot(n, l) < 0.0 && materials[u_material].double_sided > 0.5) n = -n;  // double-sided: the lit side
    float area;
    if (u_view.x < 0.5) {
        area = u_view.y * u_view.y;
    } else {
        // Solid angle of a texel: tangent size^2 * cos^3 of the off-axis angle; times distance^2.
        float c = max(dot(-l, u_axis), 1e-4);
        area = u_view.y * u_view.y * dist * dist * c * c * c;
    }
    vec3 rho = s.brdf.base_color * (1.0 - s.brdf.metallic);
    vec3 flux = dot(n, l) > 0.0 ? rho * E * (area * u_view.z) : vec3(0.0);
    out_position = vec4(v_world_pos, 1.0);
    out_normal = vec4(n, 0.0);
    out_flux = vec4(flux, sqrt(area / max(dot(n, l), 0.05)));
}
