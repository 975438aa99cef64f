#version 450 core
// GI probes, relocation (engine/effects/gi/gi.cpp), before the first update, each round from a
// trace of every probe where it stands: a probe inside geometry (a quarter or more of its rays meet back
// faces: a wall's slab, a box) is moved out through the nearest back face it saw, to a quarter of
// a cell beyond it along the face's normal (Majercik et al. 2021, "Scaling Probe-Based Real-Time Dynamic Global Illumination for
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
    // The nearest planes the rays met, by the probe's distance to them (probe_trace.comp gives each
    // hit's face: its normal towards the probe, and that distance). Moves go along a plane's
    // normal: rays that meet one plane agree on it, so a float rounding that changes which ray is
    // nearest does not change the move (moving along the nearest ray, two rays at nearly the
    // same angle to a floor 9 m away moved a probe 2.4 m apart sideways).
    float min_spacing = min(gi.spacing.x, min(gi.spacing.y, gi.spacing.z));
    float margin = GI_RELOCATE_MARGIN * min_spacing;
    // Planes at the same distance up to rounding are a tie: the grid's outer probes stand at equal
    // distances from a closed room's walls and floor by construction. A tie among back faces goes
    // to a fixed order of the normals, and a probe steps back from every front plane nearer than
    // the margin, not from the nearest alone (which one was nearest changed with the scene's
    // placement: cornell_point's corner probes stepped off the floor or off a wall).
    const float tie = 1e-4 * min_spacing;
    const vec3 order = vec3(0.5773, 0.5774, 0.5775);
    int back = 0;
    float nearest_back = 3.0e38;
    vec3 back_normal = vec3(0.0);
    vec4 near_planes[4];
    int near_count = 0;
    for (int r = 0; r < rays; ++r) {
        float a = texelFetch(t_gi_rays, 2 * (first + r)).a;
        vec4 face = texelFetch(t_gi_rays, 2 * (first + r) + 1);
        if (dot(face.xyz, face.xyz) < 0.25) continue;  // a miss
        if (a >= 0.0) {
            if (face.w >= margin) continue;
            bool known = false;
            for (int k = 0; k < near_count; ++k)
                if (dot(near_planes[k].xyz, face.xyz) > 0.999 && abs(near_planes[k].w - face.w) < 0.05 * margin) {
                    near_planes[k].w = min(near_planes[k].w, face.w);
                    known = true;
                }
            if (!known && near_count < 4) near_planes[near_count++] = face;
            continue;
        }
        ++back;  // probe_trace.comp records a back face as -0.2 x its distance
        if (face.w < nearest_back - tie) {
            nearest_back = face.w;
            back_normal = face.xyz;
        } else if (face.w <= nearest_back + tie && dot(face.xyz, order) > dot(back_normal, order)) {
            nearest_back = min(nearest_back, face.w);
            back_normal = face.xyz;
        }
    }
    ivec2 texel = ivec2(c.x + c.z * gi.probe_counts.x, c.y);
    vec3 offset = imageLoad(i_offsets, texel).xyz;
    if (back * 4 > rays) {
        // Out through the nearest back face: against its normal (which faces the probe).
        vec3 moved = offset - back_normal * (nearest_back + margin);
        if (all(lessThanEqual(abs(moved), 0.45 * gi.spacing))) offset = moved;
    } else if (near_count > 0) {
        // A probe outside geometry but nearer faces than the margin (a grid point just above a
        // floor, in a room's corner) steps back from each to the margin, for the same staircase,
        // and because its sideways light is the face's at grazing distance, which points a
        // margin away do not see.
        vec3 moved = offset;
        for (int k = 0; k < near_count; ++k) moved += near_planes[k].xyz * (margin - near_planes[k].w);
        if (all(lessThanEqual(abs(moved), 0.45 * gi.spacing))) offset = moved;
    }
    imageStore(i_offsets, texel, vec4(offset, 0.0));
}
