#version 450 core
// Depth of field, passes 2 and 3: the near field's reach. TILES: each texel is the largest
// near-field CoC radius (pixels) in its dof.tile x dof.tile block of pixels. DILATE: the largest
// over the tiles within dof.tile_reach whose circles can reach this tile, so that a pixel's gather
// radius covers every near-field blur circle that can reach it, and no more.
#include "effects/dof/dof_data.h"

layout(binding = DOF_IN_UNIT) uniform sampler2D t_in;  // TILES: colour + signed CoC; DILATE: the tiles

layout(location = 0) out vec4 out_near;

void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(t_in, 0);
    float m = 0.0;
#ifdef DILATE
    int k = dof.tile_reach;
    for (int y = -k; y <= k; ++y)
        for (int x = -k; x <= k; ++x) {
            ivec2 q = t + ivec2(x, y);
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
            // Only circles that can reach this tile: the radius beats the closest distance
            // between the two tiles' pixels.
            float r = texelFetch(t_in, q, 0).r;
            float gap = length(max(abs(vec2(x, y)) - 1.0, vec2(0.0)) * float(dof.tile));
            if (r > gap) m = max(m, r);
        }
#else
    ivec2 lo = t * dof.tile, hi = min(lo + dof.tile, size);
    for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x) m = max(m, -texelFetch(t_in, ivec2(x, y), 0).a);
#endif
    out_near = vec4(m, 0.0, 0.0, 0.0);
}
