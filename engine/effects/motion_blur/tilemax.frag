#version 450 core
// Motion blur, pass 2: TileMax (McGuire et al. 2012, section 3): per tile of tile x tile pixels,
// the half vector of largest length. With -DNEIGHBOR (pass 3, NeighborMax): per tile, the largest
// of the 3x3 tiles around it, so that a pixel's gather also reaches the motion of an object in
// the next tile that blurs over it (a blur never extends past one tile, as max_radius = tile).
#include "effects/motion_blur/motion_blur_data.h"

layout(binding = MOTION_BLUR_IN_UNIT) uniform sampler2D t_in;  // rg: half vectors (velocity, or the tiles')

layout(location = 0) out vec2 out_max;

void main() {
    ivec2 tile = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(t_in, 0) - 1;
    vec2 best = vec2(0.0);
    float best_len = -1.0;
#ifdef NEIGHBOR
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
            ivec2 q = tile + ivec2(i, j);
            if (any(lessThan(q, ivec2(0))) || any(greaterThan(q, last))) continue;
            vec2 v = texelFetch(t_in, q, 0).xy;
#else
    int k = max(motion_blur.tile, 1);
    ivec2 lo = tile * k, hi = min(lo + ivec2(k), last + 1);
    for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x) {
            vec2 v = texelFetch(t_in, ivec2(x, y), 0).xy;
#endif
            float l = dot(v, v);
            if (l > best_len) best_len = l, best = v;
        }
    out_max = best;
}
