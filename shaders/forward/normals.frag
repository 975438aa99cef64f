#version 450 core
// Depth + normal prepass of the forward path when an effect reads screen normals (SSAO, RSM): the shading normal (octahedral, as
// the G-buffer stores it), so that SSAO reads the same input on both paths.
#include "../common/scene_data.glsl"
#include "../lighting/surface.glsl"
#include "../lighting/gbuffer.glsl"

layout(location = 0) out vec4 out_normal;

void main() {
    Surface s = fragment_surface();
    out_normal = vec4(oct_encode(s.n), 0.0, 0.0);
}
