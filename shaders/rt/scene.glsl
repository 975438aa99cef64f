// The ray tracer's view of the scene (layouts mirror engine/rt/rt_geometry.hpp) and BVH
// traversal: closest hit for camera and bounce rays, any hit for shadow and AO rays.
#include "intersect.glsl"

struct RtTriangle {
    vec4 p0;  // w: material index (int bits)
    vec4 p1;  // w: node index (int bits)
    vec4 p2;
    vec4 n0;
    vec4 n1;
    vec4 n2;
    vec4 uv_a;  // uv0 of p0, uv0 of p1
    vec4 uv_b;  // uv0 of p2, uv1 of p0
    vec4 uv_c;  // uv1 of p1, uv1 of p2
    vec4 t0;    // world tangents, w = handedness (normal maps)
    vec4 t1;
    vec4 t2;
};

// RtSphere and Emitter, the spheres' and emitters' records.
#include "gpu/rt_scene.h"

// The BVH in its traversal layout (rt::pack_traversal, engine/rt/rt_geometry.hpp): 4 texels per
// interior node holding both children's boxes and refs, 3 texels per primitive in leaf order.
// Texel fetches, not SSBO loads: llvmpipe gathers them for 8 lanes at once.
layout(binding = RT_BVH_NODES_UNIT) uniform samplerBuffer t_bvh_nodes;
layout(binding = RT_BVH_PRIMS_UNIT) uniform samplerBuffer t_bvh_prims;
// The triangles (rt::TriangleGpu), 12 texels each, read through load_triangle().
layout(binding = RT_TRIANGLES_UNIT) uniform samplerBuffer t_triangles;
#ifdef HAS_VERTEX_COLORS
// COLOR_0 at the triangles' corners (rt::RtGeometry::colors), 3 texels each.
layout(binding = RT_COLORS_UNIT) uniform samplerBuffer t_colors;
#endif

RtTriangle load_triangle(int i) {
    int b = i * 12;
    RtTriangle t;
    t.p0 = texelFetch(t_triangles, b);
    t.p1 = texelFetch(t_triangles, b + 1);
    t.p2 = texelFetch(t_triangles, b + 2);
    t.n0 = texelFetch(t_triangles, b + 3);
    t.n1 = texelFetch(t_triangles, b + 4);
    t.n2 = texelFetch(t_triangles, b + 5);
    t.uv_a = texelFetch(t_triangles, b + 6);
    t.uv_b = texelFetch(t_triangles, b + 7);
    t.uv_c = texelFetch(t_triangles, b + 8);
    t.t0 = texelFetch(t_triangles, b + 9);
    t.t1 = texelFetch(t_triangles, b + 10);
    t.t2 = texelFetch(t_triangles, b + 11);
    return t;
}
layout(std430, binding = RT_SPHERES_BINDING) readonly buffer Spheres { RtSphere spheres[]; };
layout(std430, binding = RT_EMITTERS_BINDING) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = RT_SURFACES_BINDING) readonly buffer Surfaces { Emitter surfaces[]; };  // every triangle by area

// The frame block `rt`.
#include "gpu/rt_frame.h"

// Scene images as array layers (layer = image index; GpuScene::image_array).
layout(binding = RT_IMAGES_UNIT) uniform sampler2DArray t_images;
// The same storage viewed as sRGB (GpuScene::image_array_srgb): colour slots (base colour,
// emissive) decode before filtering, as the rasterizer's sRGB textures do.
layout(binding = RT_IMAGES_SRGB_UNIT) uniform sampler2DArray t_images_srgb;

// The glTF sampler's wrap mode per axis (wrap_modes: 4 bits per slot, s then t; 0 repeat,
// 1 clamp to edge, 2 mirrored repeat), applied by hand: the image array itself repeats.
float wrap_coordinate(float x, int mode, float size) {
    if (mode == 1) return clamp(x, 0.5 / size, 1.0 - 0.5 / size);
    if (mode == 2) {
        float m = mod(x, 2.0);
        return clamp(m > 1.0 ? 2.0 - m : m, 0.5 / size, 1.0 - 0.5 / size);
    }
    return x;
}

vec2 material_uv(MaterialData m, int slot, int set, vec2 uv0, vec2 uv1) {
    vec3 uv = vec3(set == 1 ? uv1 : uv0, 1.0);
    vec2 r = vec2(dot(m.uv_transform[slot * 2].xyz, uv), dot(m.uv_transform[slot * 2 + 1].xyz, uv));
    int wrap = (m.wrap_modes >> (4 * slot)) & 15;
    if (wrap != 0) {
        vec2 size = vec2(textureSize(t_images, 0).xy);
        r = vec2(wrap_coordinate(r.x, wrap & 3, size.x), wrap_coordinate(r.y, wrap >> 2, size.y));
    }
    return r;
}
// A material's texture in one slot (0 base colour, 1 metallic-roughness, 2 normal, 3 occlusion,
// 4 emissive) at a hit, linear values (colour slots decoded from sRGB): its uv set and transform,
// the sampler's wrap modes, and its filter: a
// NEAREST magnification filter (nearest_magnification bit per slot) fetches the texel under uv (the array's
// layers replicate each image's texels, exact when the image's size divides the layer's), else
// bilinear at level 0 (supersampling integrates the pixel's footprint).
vec4 material_texture(MaterialData m, int slot, int image, int set, vec2 uv0, vec2 uv1) {
    vec2 uv = material_uv(m, slot, set, uv0, uv1);
    bool srgb = slot == 0 || slot == 4;
    if (((m.nearest_magnification >> slot) & 1) != 0) {
        ivec2 size = textureSize(t_images, 0).xy;
        ivec3 texel = ivec3(clamp(ivec2(floor(fract(uv) * vec2(size))), ivec2(0), size - 1), image);
        return srgb ? texelFetch(t_images_srgb, texel, 0) : texelFetch(t_images, texel, 0);
    }
    return srgb ? textureLod(t_images_srgb, vec3(uv, float(image)), 0.0) : textureLod(t_images, vec3(uv, float(image)), 0.0);
}

struct Hit {
    float t;
    int prim;   // < counts.x: triangle, else sphere (prim - counts.x); -1: miss
    vec2 bary;
};

const int kStackSize = 64;
// The traversal stacks live in shared memory, entry k of invocation i at k * group size + i (the
// including shader declares its local size first). On llvmpipe this measured 12% more camera rays
// and 36% more AO rays per second than a local array, which it indexes per lane through scratch.
const uint kGroupInvocations = gl_WorkGroupSize.x * gl_WorkGroupSize.y * gl_WorkGroupSize.z;
shared int traversal_stack[kStackSize * kGroupInvocations];

// One traversal for both kinds of query: `any_hit` returns at the first hit found (shadow and AO
// rays), otherwise the closest hit is kept and used to prune. Near child first, an explicit stack
// of node refs (>= 0 interior node, < 0 leaf: -1 - (first * 64 + count - 1)).
// The loop is "while-while" (Aila & Laine 2009, "Understanding the efficiency of ray traversal on
// GPUs"): interior nodes until a leaf, then leaves until an interior node. llvmpipe runs 8
// invocations in SIMD lanes and executes every branch some lane takes; one loop with an if/else
// pays for the node visit and the leaf's triangles in every iteration where the lanes disagree.
// On llvmpipe this measured 1.5x the camera rays and 1.9x the AO rays per second of that loop.
const int kTraversalDone = int(0x80000000);  // below every leaf ref (rt::kTraversalNoChild)

#ifdef RT_STATS
// One traversal step (a node or a leaf) of the invocations that run it together in one subgroup:
// their first lane adds the subgroup's size, so that (steps of all lanes) / (lane slots) is the
// fraction of SIMD lanes that did useful work; lanes waiting for the others count as idle.
uint traversal_slots() {
#ifdef GL_ARB_shader_ballot
    uint64_t lanes = ballotARB(true);
    uint low = uint(lanes), high = uint(lanes >> 32);
    int first = low != 0u ? findLSB(low) : 32 + findLSB(high);
    return gl_SubGroupInvocationARB == uint(first) ? gl_SubGroupSizeARB : 0u;
#else
    return 0u;
#endif
}
#endif

// `seen`: the ray looks for what it sees (camera, reflection, refraction and bounce rays). glTF's
// doubleSided false means back-face culling, so such a ray passes through the back of a
// single-sided opaque triangle, as the rasterizer (forward, deferred, reflection probes) never
// draws it; pack_traversal marks those triangles (the w of their second texel). Occlusion rays
// (shadow, AO, next-event estimation) are blocked by both sides, as shadow maps draw casters with
// no face culling. Transmissive surfaces are never culled: a ray inside a solid sees its interface
// from behind.
Hit trace(Ray ray, float tmax, bool any_hit, bool seen) {
    Hit hit;
    hit.t = tmax;
    hit.prim = -1;
    hit.bary = vec2(0.0);
    if (rt.triangle_count + rt.sphere_count == 0) return hit;
    WatertightRay w = watertight_setup(ray);
    vec3 inv_dir = 1.0 / ray.dir;
    int stack_base = int(gl_LocalInvocationIndex);
    int sp = 0;
    int ref = 0;
#ifdef RT_STATS
    uint visited = 0u, tested = 0u, slots = 0u;
    atomicAdd(traversal_rays, 1u);
#endif
    while (true) {
        while (ref >= 0) {
#ifdef RT_STATS
            ++visited;
            slots += traversal_slots();
#endif
            int b = ref * 4;
            vec4 lmin = texelFetch(t_bvh_nodes, b), lmax = texelFetch(t_bvh_nodes, b + 1);
            vec4 rmin = texelFetch(t_bvh_nodes, b + 2), rmax = texelFetch(t_bvh_nodes, b + 3);
            float tl = intersect_aabb(lmin.xyz, lmax.xyz, ray.origin, inv_dir, hit.t);
            float tr = intersect_aabb(rmin.xyz, rmax.xyz, ray.origin, inv_dir, hit.t);
            int left = floatBitsToInt(lmin.w), right = floatBitsToInt(rmin.w);
            bool hl = tl >= 0.0, hr = tr >= 0.0;
            if (hl && hr) {
                bool left_first = tl <= tr;
                if (sp < kStackSize) traversal_stack[sp++ * int(kGroupInvocations) + stack_base] = left_first ? right : left;
                ref = left_first ? left : right;
            } else if (hl || hr) {
                ref = hl ? left : right;
            } else {
                ref = sp == 0 ? kTraversalDone : traversal_stack[--sp * int(kGroupInvocations) + stack_base];
            }
        }
        if (ref == kTraversalDone) break;
        while (ref < 0 && ref != kTraversalDone) {
            int code = -1 - ref;
            int first = code >> 6, count = (code & 63) + 1;
#ifdef RT_STATS
            ++visited;
            tested += uint(count);
            slots += traversal_slots();
#endif
            for (int i = 0; i < count; ++i) {
                int r = (first + i) * 3;
                vec4 a = texelFetch(t_bvh_prims, r);
                int prim = floatBitsToInt(a.w);
                float t;
                vec2 bary = vec2(0.0);
#ifndef RT_NO_SPHERES
                if (prim < rt.triangle_count) {
#endif
                    vec4 b1 = texelFetch(t_bvh_prims, r + 1), b2 = texelFetch(t_bvh_prims, r + 2);
                    t = intersect_triangle(w, a.xyz, b1.xyz, b2.xyz, hit.t, bary);
                    if (seen && b1.w > 0.5 && t > 0.0 && dot(cross(b1.xyz - a.xyz, b2.xyz - a.xyz), ray.dir) >= 0.0) t = -1.0;
#ifdef HAS_MASK
                    // alphaMode MASK: texels below the cutoff are holes, for every kind of ray.
                    if (t > 0.0 && t < hit.t) {
                        // Only the mode is read for every candidate: copying the whole material
                        // here costs a third of the ray rate on llvmpipe.
                        int mi = floatBitsToInt(texelFetch(t_triangles, prim * 12).w);
                        if (int(materials[mi].alpha_mode) == 1) {
                            float alpha = materials[mi].base_color.a;
                            if (materials[mi].texcoord.x >= 0) {
                                MaterialData m = materials[mi];
                                RtTriangle tri = load_triangle(prim);
                                float w0 = 1.0 - bary.x - bary.y;
                                vec2 uv0 = tri.uv_a.xy * w0 + tri.uv_a.zw * bary.x + tri.uv_b.xy * bary.y;
                                vec2 uv1 = tri.uv_b.zw * w0 + tri.uv_c.xy * bary.x + tri.uv_c.zw * bary.y;
                                alpha *= material_texture(m, 0, m.images.x, m.texcoord.x, uv0, uv1).a;
                            }
#ifdef HAS_VERTEX_COLORS
                            float w0c = 1.0 - bary.x - bary.y;
                            alpha *= texelFetch(t_colors, prim * 3).a * w0c + texelFetch(t_colors, prim * 3 + 1).a * bary.x +
                                     texelFetch(t_colors, prim * 3 + 2).a * bary.y;
#endif
                            if (alpha < materials[mi].alpha_cutoff) t = -1.0;
                        }
                    }
#endif
#ifndef RT_NO_SPHERES
                } else {
                    t = intersect_sphere(ray, a.xyz, texelFetch(t_bvh_prims, r + 1).x, 0.0, hit.t);
                }
#endif
                if (t > 0.0 && t < hit.t) {
                    hit.t = t;
                    hit.prim = prim;
                    hit.bary = bary;
                    if (any_hit) {
#ifdef RT_STATS
                        atomicAdd(traversal_nodes, visited);
                        atomicAdd(traversal_primitives, tested);
                        atomicAdd(traversal_lane_slots, slots);
#endif
                        return hit;
                    }
                }
            }
            ref = sp == 0 ? kTraversalDone : traversal_stack[--sp * int(kGroupInvocations) + stack_base];
        }
        if (ref == kTraversalDone) break;
    }
#ifdef RT_STATS
    atomicAdd(traversal_nodes, visited);
    atomicAdd(traversal_primitives, tested);
    atomicAdd(traversal_lane_slots, slots);
#endif
    return hit;
}

// The closest surface that the ray sees (back faces of single-sided opaque triangles culled).
Hit trace_seen(Ray ray, float tmax) { return trace(ray, tmax, false, true); }
// The closest surface on the ray, either side.
Hit trace_closest(Ray ray, float tmax) { return trace(ray, tmax, false, false); }
// True if anything lies on the ray within (0, tmax), either side.
bool trace_any(Ray ray, float tmax) { return trace(ray, tmax, true, false).prim >= 0; }

// Surface data at a hit.
struct SurfaceHit {
    vec3 p;
    vec3 ng;        // geometric normal, facing the incoming ray
    vec3 ns;        // shading normal, same side as ng
    bool front;     // the ray hit the front (the side the geometric normal points to)
    int material;
    vec2 uv0;
    vec2 uv1;
    vec4 color;     // COLOR_0 (1 without vertex colours), multiplies the base colour as in the raster
#ifdef MATERIAL_LAYERS
    vec3 ni;        // the interpolated normal (ns before the normal map) and its unit tangent
    vec3 t;         // frame, for the material layers (coat normal map, anisotropy)
    vec3 b;
#endif
};

SurfaceHit surface_at(Ray ray, Hit hit) {
    SurfaceHit s;
    s.p = ray.origin + ray.dir * hit.t;
    // Compiled for what the scene has (ray_tracer.cpp's defines): llvmpipe runs both sides of a
    // branch under a lane mask, so code the scene cannot reach still costs every hit.
#ifndef RT_NO_SPHERES
    if (hit.prim < rt.triangle_count) {
#endif
        RtTriangle tri = load_triangle(hit.prim);
        vec3 ng = normalize(cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz));
        float w0 = 1.0 - hit.bary.x - hit.bary.y;
        vec3 ns = tri.n0.xyz * w0 + tri.n1.xyz * hit.bary.x + tri.n2.xyz * hit.bary.y;
        float len = length(ns);
        ns = len > 1e-12 ? ns / len : ng;
        // Interpolated normals may point away from the geometric side; keep them together.
        if (dot(ns, ng) < 0.0) ns = -ns;
        s.material = floatBitsToInt(tri.p0.w);
        s.front = dot(ng, ray.dir) < 0.0;
        s.ng = s.front ? ng : -ng;
        s.ns = s.front ? ns : -ns;
        // Exact positions from barycentrics are more accurate than origin + t * dir far away.
        s.p = tri.p0.xyz * w0 + tri.p1.xyz * hit.bary.x + tri.p2.xyz * hit.bary.y;
        s.uv0 = tri.uv_a.xy * w0 + tri.uv_a.zw * hit.bary.x + tri.uv_b.xy * hit.bary.y;
        s.uv1 = tri.uv_b.zw * w0 + tri.uv_c.xy * hit.bary.x + tri.uv_c.zw * hit.bary.y;
#ifdef HAS_VERTEX_COLORS
        s.color = texelFetch(t_colors, hit.prim * 3) * w0 + texelFetch(t_colors, hit.prim * 3 + 1) * hit.bary.x +
                  texelFetch(t_colors, hit.prim * 3 + 2) * hit.bary.y;
#else
        s.color = vec4(1.0);
#endif
#ifdef MATERIAL_LAYERS
        {
            s.ni = s.ns;
            vec3 tg = tri.t0.xyz * w0 + tri.t1.xyz * hit.bary.x + tri.t2.xyz * hit.bary.y;
            vec3 t = tg - s.ni * dot(s.ni, tg);
            float tl = length(t);
            if (tl > 1e-8) {
                s.t = t / tl;
                s.b = cross(s.ni, s.t) * (tri.t0.w < 0.0 ? -1.0 : 1.0) * (s.front ? 1.0 : -1.0);
            } else {
                onb(s.ni, s.t, s.b);
            }
        }
#endif
#ifndef RT_NO_TEXTURES
        // Normal map, as the forward pass applies it (tangent frame from the interpolated tangent).
        int mi = s.material;
        if (materials[mi].texcoord.z >= 0) {
            MaterialData m = materials[mi];
            vec3 tg = tri.t0.xyz * w0 + tri.t1.xyz * hit.bary.x + tri.t2.xyz * hit.bary.y;
            vec3 t = tg - s.ns * dot(s.ns, tg);
            float tl = length(t);
            if (tl > 1e-8) {
                t /= tl;
                vec3 b = cross(s.ns, t) * (tri.t0.w < 0.0 ? -1.0 : 1.0) * (s.front ? 1.0 : -1.0);
                vec3 tn = material_texture(m, 2, m.images.z, m.texcoord.z, s.uv0, s.uv1).xyz * 2.0 - 1.0;
                tn.xy *= m.normal_scale;
                vec3 mapped = mat3(t, b, s.ns) * tn;
                float ml = length(mapped);
                if (ml > 1e-8) s.ns = mapped / ml;
                // Keep the shading normal on the side the ray came from.
                float side = dot(s.ns, s.ng);
                if (side < 1e-4) s.ns = normalize(s.ns + s.ng * (1e-4 - side));
            }
        }
#endif
        // Shading normals (interpolated or mapped) that face away from the viewer are bent back
        // to the horizon, exactly as the rasterizer does (shaders/lighting/surface.glsl), so
        // that the BRDF sees the same n.v in both. ns and v both lie above the geometric
        // surface, so the bent normal does too. Directions that the shading normal's BRDF sends
        // below the geometric surface are handled by the folded BRDF in brdf_sampling.glsl.
        vec3 v = -normalize(ray.dir);
        float nv = dot(s.ns, v);
        if (nv < 1e-4) s.ns = normalize(s.ns + v * (1e-4 - nv));
#ifndef RT_NO_SPHERES
    } else {
        RtSphere sp = spheres[hit.prim - rt.triangle_count];
        vec3 n = normalize(s.p - sp.center);
        // Project the point back onto the sphere: removes the error of origin + t * dir.
        s.p = sp.center + n * sp.radius;
        s.material = sp.material;
        s.front = dot(n, ray.dir) < 0.0;
        s.ng = s.front ? n : -n;
        s.ns = s.ng;
        s.uv0 = direction_to_equirect(n);  // spheres carry no mesh UVs here
        s.uv1 = s.uv0;
        s.color = vec4(1.0);
#ifdef MATERIAL_LAYERS
        s.ni = s.ns;
        onb(s.ni, s.t, s.b);
#endif
    }
#endif
    return s;
}
