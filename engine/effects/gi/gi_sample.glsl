// Irradiance from the GI probe grid at a surface point (engine/effects/gi/gi.cpp): included by
// the raster's shading (gi_shading.glsl) and by the probes' own trace (probe_trace.comp), which
// reads the previous iteration's probes for the next bounce. The method is Majercik et al. 2019,
// "Dynamic Diffuse Global Illumination with Ray-Traced Irradiance Fields" (JCGT 8(2)): probes on a
// grid store octahedral maps of irradiance and of the first two moments of the distance to the
// nearest surface; a point blends the 8 probes of its cell, weighted trilinearly, by how much the
// probe lies in front of the surface, and by a Chebyshev bound on the probe seeing the point.
#include "effects/gi/gi_data.h"

layout(binding = GI_IRRADIANCE_UNIT) uniform sampler2D t_gi_irradiance;
layout(binding = GI_DEPTH_UNIT) uniform sampler2D t_gi_depth;
// Each probe's offset from its grid point (probe_relocate.comp: a probe inside geometry is moved
// out of it); the trilinear weights stay those of the grid.
layout(binding = GI_OFFSETS_UNIT) uniform sampler2D t_gi_offsets;

// Octahedral map of the unit sphere onto [-1, 1]^2 (Cigolle et al. 2014, JCGT 3(2)).
vec2 gi_oct_encode(vec3 n) {
    vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if (n.z < 0.0) p = (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
    return p;
}

vec3 gi_oct_decode(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

ivec3 gi_probe_coord(int index) {
    return ivec3(index % gi.probe_counts.x, (index / gi.probe_counts.x) % gi.probe_counts.y, index / (gi.probe_counts.x * gi.probe_counts.y));
}

vec3 gi_probe_grid_position(ivec3 c) { return gi.origin + vec3(c) * gi.spacing; }
vec3 gi_probe_position(ivec3 c) {
    return gi_probe_grid_position(c) + texelFetch(t_gi_offsets, ivec2(c.x + c.z * gi.probe_counts.x, c.y), 0).xyz;
}

// A probe's tile in an atlas: tiles side by side, x = i + k * nx, y = j; each tile has a one-texel
// border that repeats the octahedral map across its edges, so bilinear filtering stays on the sphere.
vec2 gi_atlas_uv(ivec3 c, vec3 dir, int interior, vec2 atlas_size) {
    vec2 tile = vec2(float(c.x + c.z * gi.probe_counts.x), float(c.y)) * float(interior + 2) + 1.0;
    return (tile + (gi_oct_encode(dir) * 0.5 + 0.5) * float(interior)) / atlas_size;
}

// Irradiance E at p for the normal n (v: unit vector from p towards the viewer, which the
// sampling point is moved towards, with the normal, to stay off the surface the probes saw).
vec3 gi_irradiance(vec3 p, vec3 n, vec3 v) {
    if (gi.on < 0.5) return vec3(0.0);
    vec3 biased = p + (0.2 * n + 0.8 * v) * gi.shading_bias;
    ivec3 last = max(gi.probe_counts - 1, ivec3(0));
    vec3 g = (biased - gi.origin) / gi.spacing;
    ivec3 base = clamp(ivec3(floor(g)), ivec3(0), max(last - 1, ivec3(0)));
    vec3 alpha = clamp(g - vec3(base), vec3(0.0), vec3(1.0));
    vec2 irr_size = vec2(textureSize(t_gi_irradiance, 0));
    vec2 depth_size = vec2(textureSize(t_gi_depth, 0));
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        ivec3 c = min(base + offset, last);
        vec3 tri3 = mix(1.0 - alpha, alpha, vec3(offset));
        float trilinear = tri3.x * tri3.y * tri3.z;
        if (trilinear <= 0.0) continue;
        vec3 probe = gi_probe_position(c);
        // Probes behind the surface count less (a smooth cosine, never zero: DDGI's "wrap shading").
        vec3 to_probe = probe - p;
        float len = length(to_probe);
        float facing = len > 0.0 ? (dot(to_probe / len, n) + 1.0) * 0.5 : 1.0;
        float w = facing * facing + 0.2;
        // Chebyshev's inequality on the distance moments the probe saw in this direction: the
        // probability that the probe sees the (biased) point.
        vec3 from_probe = biased - probe;
        float d = length(from_probe);
        if (d > 0.0) {
            vec2 m = textureLod(t_gi_depth, gi_atlas_uv(c, from_probe / d, gi.depth_texels, depth_size), 0.0).rg;
            if (d > m.x) {
                float variance = abs(m.y - m.x * m.x);
                float excess = d - m.x;
                float chebyshev = variance / (variance + excess * excess);
                w *= max(chebyshev * chebyshev * chebyshev, 0.05);
            }
        }
        w = max(w, 1e-6);
        // Crush tiny weights (DDGI): a probe that barely sees the point should not tint it.
        const float crush = 0.2;
        if (w < crush) w *= w * w / (crush * crush);
        vec4 e = textureLod(t_gi_irradiance, gi_atlas_uv(c, n, gi.irradiance_texels, irr_size), 0.0);
        w *= trilinear * e.a;  // a: the probe is active (it is not inside geometry)
        sum += e.rgb * w;
        wsum += w;
    }
    return wsum > 0.0 ? sum / wsum : vec3(0.0);
}
