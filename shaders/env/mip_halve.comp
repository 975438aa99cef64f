#version 450 core
// One mip level of an RGBA32F texture from the level above it, for power-of-two sizes: what
// Mesa's glGenerateTextureMipmap computes on llvmpipe (a blit with a linear filter from level
// L-1 to level L), texel for texel, so that the image does not change (engine/render/
// environment.hpp, float_mipmaps; tests/unit/test_gl_worker.cpp compares every level). At an
// exact 2:1 reduction the blit samples each destination texel's centre, between four source
// texels with weights 1/2: llvmpipe's lerp a + w (b - a), along x on both rows, then along y.
// A side already 1 texel long repeats its texel (clamp to edge; the weight there is 0, and
// a + 0 (a - a) = a as well).
// CUBE_ARRAY: a cube-map array, each face on its own (gl_GlobalInvocationID.z = layer-face);
// otherwise a 2D texture.
#include "gpu/bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
#ifdef CUBE_ARRAY
layout(rgba32f, binding = MIP_SRC_IMAGE) uniform readonly imageCubeArray src;
layout(rgba32f, binding = MIP_DST_IMAGE) uniform writeonly imageCubeArray dst;
#define AT(x, y) ivec3(x, y, int(gl_GlobalInvocationID.z))
#else
layout(rgba32f, binding = MIP_SRC_IMAGE) uniform readonly image2D src;
layout(rgba32f, binding = MIP_DST_IMAGE) uniform writeonly image2D dst;
#define AT(x, y) ivec2(x, y)
#endif
layout(location = 0) uniform ivec2 u_src_size;  // of level L-1
layout(location = 1) uniform ivec2 u_dst_size;  // of level L

void main() {
    ivec2 id = ivec2(gl_GlobalInvocationID.xy);
    if (id.x >= u_dst_size.x || id.y >= u_dst_size.y) return;
    ivec2 a = min(2 * id, u_src_size - 1), b = min(2 * id + 1, u_src_size - 1);
    vec4 t00 = imageLoad(src, AT(a.x, a.y)), t10 = imageLoad(src, AT(b.x, a.y));
    vec4 t01 = imageLoad(src, AT(a.x, b.y)), t11 = imageLoad(src, AT(b.x, b.y));
    vec4 r0 = t00 + 0.5 * (t10 - t00);
    vec4 r1 = t01 + 0.5 * (t11 - t01);
    imageStore(dst, AT(id.x, id.y), r0 + 0.5 * (r1 - r0));
}
