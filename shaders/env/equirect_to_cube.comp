#version 450 core
// An equirectangular environment map resampled into mip 0 of a cube map (one cube of a cube-map
// array), filtered at the mip of the equirect map whose texels match the cube's in size.
#include "gpu/bindings.h"
#include "../common/math.glsl"
#include "cube.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = SOURCE_UNIT) uniform sampler2D t_equirect;  // linear, mipmapped, repeat in u
layout(rgba32f, binding = DST_IMAGE) uniform writeonly imageCubeArray cube;
layout(location = 0) uniform int u_size;

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= u_size || id.y >= u_size) return;
    vec3 d = cube_texel_direction(id.z, id.xy, u_size);
    // Four cube faces span the equirect map's width.
    float lod = max(log2(float(textureSize(t_equirect, 0).x) / (4.0 * float(u_size))), 0.0);
    vec3 c = textureLod(t_equirect, direction_to_equirect(d), lod).rgb;
    imageStore(cube, id, vec4(max(c, vec3(0.0)), 1.0));
}
