#version 450 core
// GI probes, relocation (engine/effects/gi/gi.cpp), before the first update, each round from a
// trace of every probe where it stands: a probe inside geometry (a quarter or more of its rays meet back
// faces: a wall's slab, a box) is moved out through the nearest back face it saw, to a quarter of
// a cell beyond it (Majercik et al. 2021, "Scaling Probe-Based Real-Time Dynamic Global Illumination for
// Production", JCGT 10(2): probe relocation). Without it such a probe is switched off, and the
// surfaces next to it take their light from probes a whole cell away, inside the room: a closed
// room's outer layer of probes sits in its walls, and its walls, floor and ceiling were lit by
// probes nearer its middle (+9 to +25 % of the first bounce in bright rooms). An offset stays
// within 0.45 of a cell of the grid point, so that the cell's trilinear weights still fit it; a
// probe that cannot leave within that stays where it is, switched off. A few rounds: a probe in a
// floor slab under a wall comes up into the wall, and leaves it in the next round.
#include "common/math.glsl"
#include "effects/gi/gi_sample.glsl"
layout(local_size_x = 64) in;
// How far beyond the face a moved probe stands, in units of the smallest spacing: closer than
// about 0.2 and the face's own points, seen by the probe at grazing distance through its coarse
// distance map, show the Chebyshev test's staircase (cornell_point's tall box at 0.05 and 0.15).
const float GI_RELOCATE_MARGIN = 0.25;


layout(binding = GI_RAYS_UNIT) uniform samplerBuffer t_gi_rays;
layout(binding = GI_OFFSETS_IMAGE, rgba32f) uniform image2D i_offsets;

void main() {
    int total = gi.probe_counts.x * gi.probe_counts.y * gi.probe_counts.z;
    int probe = int(gl_GlobalInvocationID.x);
    if (probe >= total) return;
    ivec3 c = gi_probe_coord(probe);
    int rays = gi.rays_per_probe;
    int first = probe * rays;
    int back = 0;
    float nearest_back = 3.0e38, nearest_front = 3.0e38;
    vec3 nearest_back_dir = vec3(0.0), nearest_front_dir = vec3(0.0);
    for (int r = 0; r < rays; ++r) {
        float a = texelFetch(t_gi_rays, 2 * (first + r)).a;
        if (a >= 0.0) {
            if (a < nearest_front) {
                nearest_front = a;
                nearest_front_dir = texelFetch(t_gi_rays, 2 * (first + r) + 1).xyz;
            }
            continue;
        }
        ++back;
        // probe_trace.comp records a back face as -0.2 x its distance.
        float d = -a / 0.2;
        if (d < nearest_back) {
            nearest_back = d;
            nearest_back_dir = texelFetch(t_gi_rays, 2 * (first + r) + 1).xyz;
        }
    }
    ivec2 texel = ivec2(c.x + c.z * gi.probe_counts.x, c.y);
    vec3 offset = imageLoad(i_offsets, texel).xyz;
    float min_spacing = min(gi.spacing.x, min(gi.spacing.y, gi.spacing.z));
    float margin = GI_RELOCATE_MARGIN * min_spacing;
    if (back * 4 > rays) {
        vec3 moved = offset + nearest_back_dir * (nearest_back + margin);
        if (all(lessThanEqual(abs(moved), 0.45 * gi.spacing))) offset = moved;
    } else if (nearest_front < margin) {
        // A probe outside geometry but nearer a face than the margin (a grid point just above a
        // floor) steps back from it to the margin, for the same staircase, and because its
        // sideways light is the face's at grazing distance, which points a margin away do not see.
        vec3 moved = offset - nearest_front_dir * (margin - nearest_front);
        if (all(lessThanEqual(abs(moved), 0.45 * gi.spacing))) offset = moved;
    }
    imageStore(i_offsets, texel, vec4(offset, 0.0));
}
