// The ray tracer's frame block, declared once for C++ (engine/rt/ray_tracer.cpp and the GI
// probes fill it) and GLSL (shaders/rt/scene.glsl reads it as `rt`), through gpu/gpu_block.h.
#ifndef CANDELA_GPU_RT_FRAME_H
#define CANDELA_GPU_RT_FRAME_H

#include "gpu/bindings.h"
#include "gpu/gpu_block.h"

GPU_NAMESPACE_BEGIN

GPU_BLOCK(RtFrame, RT_FRAME_BINDING) {
    mat4 inv_view_proj;        // camera-relative: of the view without its translation
    vec4 camera_pos;           // xyz
    vec3 env_radiance;         // constant radiance, or the map's scale when env_map_bound = 1
    float env_map_bound;
    int triangle_count;
    int sphere_count;
    int emitter_count;
    int punctual_light_count;
    int surface_count;         // triangles with an area
    int env_width;             // environment map size (importance sampling)
    int env_height;
    int dispatch_samples;      // samples per pixel of this dispatch (0 counts as 1)
    int width;                 // image size
    int height;
    int sample_index;          // the dispatch's first sample
    int seed;
    int max_depth;
    int jitter;                // 1: jitter the camera rays in the pixel
    int indirect_occlusion;    // mode indirect: 1 to trace the occlusion
    int tile_y;                // the dispatch's first row
    float ao_radius;
    float whitted_max_roughness;
    float emitted_power;       // total power of the emitters
    float visibility_light;    // mode visibility: the light (an index)
    float ray_offset;          // smallest secondary-ray offset (rt::ray_offset_for_extent)
    float sample_stride;       // samples of a dispatch are sample_index + k * stride (--spp-shard's N;
                               // 0 counts as 1)
    float camera_hides_emission;  // 1: camera rays do not see emission or the environment
                                  // (path/direct: Options::camera_sees_emission)
    float dielectric_highlights;  // 1: dielectric interfaces reflect the punctual lights
                                  // (path/direct: Options::dielectric_highlights)
    float caustics_only;          // 1: path counts caustic paths alone (Options::caustics_only)
    float emitters_only;          // 1: path counts the emitters' light alone (Options::emitters_only)
    float pad1, pad2;
    // The thin lens (depth of field): lens_x / lens_y.xyz the lens disk's axes (the camera's x and
    // y) scaled by its radius, lens_x.w the radius (0: a pinhole), lens_y.w the focus distance
    // along lens_axis.xyz (the view axis, unit length). Zero unless has_thin_lens(camera).
    vec4 lens_x;
    vec4 lens_y;
    vec4 lens_axis;
} GPU_BLOCK_INSTANCE(rt);
GPU_BLOCK_CHECK(RtFrame, 256)

GPU_NAMESPACE_END

#endif
