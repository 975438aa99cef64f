// The texture units, image units and buffer binding points of the base passes and the ray tracer,
// named once for C++ (glBindTextureUnit, glBindBufferBase...) and GLSL (layout(binding = ...)).
// Each kind of binding point is its own namespace in GL: uniform buffer 0 and storage buffer 0
// are different points, as are texture unit 0 and image unit 0. Effects name theirs in their own
// *_data.h; the points used while the scene is drawn (the frame, materials, lights, material
// textures, environment) must not meet an effect's, whose maps are bound through a whole frame.
// Used points, for a new binding: `grep -rn '_UNIT\|_BINDING\|_IMAGE' engine/gpu engine/effects`.
#ifndef CANDELA_GPU_BINDINGS_H
#define CANDELA_GPU_BINDINGS_H

// Uniform buffers.
#define FRAME_BINDING 0     // FrameData (gpu/scene_blocks.h): the rasterizer's frame
#define RT_FRAME_BINDING 8  // RtFrame (gpu/rt_frame.h): the tracer's frame

// Storage buffers.
#define MATERIALS_BINDING 1            // MaterialData[] (GpuScene::materials)
#define LIGHTS_BINDING 2               // LightData[] (GpuScene::lights): punctual lights first
#define RT_SPHERES_BINDING 6           // RtScene's spheres
#define RT_EMITTERS_BINDING 7          // RtScene's emitters by power, with their cdf
#define RT_ACCUM_BINDING 9             // the tracer's accumulation (rgb sum, sample count)
#define RT_DIAGNOSTICS_BINDING 10      // the tracer's counters (non-finite samples, statistics)
#define RT_SURFACES_BINDING 11         // every triangle by area
#define RT_ENV_DISTRIBUTION_BINDING 12 // environment-map importance sampling
#define AA_EDGE_STATS_BINDING 14       // deferred lighting's edge statistics (light.comp)
#define EDGE_DISPATCH_BINDING 15       // deferred lighting's indirect dispatch of edge groups
#define LIGHT_TILES_BINDING 16         // the forward pass's per-tile light masks (forward/light_tiles.comp)

// Texture units while the scene is drawn: the material's textures (a draw's slot s at unit
// BASE_COLOR_UNIT + s), the environment, the BRDF table.
#define BASE_COLOR_UNIT 0
#define METALLIC_ROUGHNESS_UNIT 1
#define NORMAL_UNIT 2
#define OCCLUSION_UNIT 3
#define EMISSIVE_UNIT 4
#define MATERIAL_UNIT_COUNT 5
#define ENVIRONMENT_UNIT 5       // the equirectangular environment map (rasterizer and tracer)
#define ENV_CUBE_UNIT 6          // the static environment cube, when FrameData::env_cube_bound
#define OPAQUE_DEPTH_UNIT 11     // depth peeling: the opaque surfaces' depth
#define PREVIOUS_LAYER_UNIT 12   // depth peeling: the previous layer's depth
#define BRDF_LUT_UNIT 13         // split-sum BRDF table
#define MATERIAL_IMAGES_UNIT 24  // the material extensions' textures: the scene images as array layers
#define MATERIAL_IMAGES_SRGB_UNIT 25  // (GpuScene::image_array, as in the tracer; shaders/common/material_layers.glsl)

// Texture units of the tracer (and of compute programs over shaders/rt/scene.glsl).
#define RT_IMAGES_UNIT 6         // scene images as array layers (GpuScene::image_array)
#define RT_IMAGES_SRGB_UNIT 15   // the same storage as sRGB
#define RT_BVH_NODES_UNIT 16     // buffer textures of the BVH (rt::pack_traversal)
#define RT_BVH_PRIMS_UNIT 17
#define RT_TRIANGLES_UNIT 18
#define RT_COLORS_UNIT 26        // the triangles' vertex colours, 3 texels each (HAS_VERTEX_COLORS)

// Full-screen and compute passes of the base: their inputs, bound just for the pass.
#define SOURCE_UNIT 0            // copy, mip_downsample, tonemap's HDR input, the environment's
                                 // equirectangular map and prefilter source
#define GBUFFER_BASE_UNIT 0      // deferred lighting's G-buffer: base colour and occlusion,
#define GBUFFER_NORMAL_UNIT 1    // normal, roughness and metallic,
#define GBUFFER_F0_UNIT 2        // F0 and F90,
#define GBUFFER_DEPTH_UNIT 3     // depth (gbuffer_resolve: 0 depth, 1 normal, as below)
#define RESOLVE_DEPTH_UNIT 0     // gbuffer_resolve.frag's multisampled depth and normals
#define RESOLVE_NORMAL_UNIT 1
#define DEBUG_2D_UNIT 0          // debug_view.frag: one of the three, by texture kind
#define DEBUG_ARRAY_UNIT 1
#define DEBUG_CUBE_UNIT 2

// Image units.
#define DST_IMAGE 0              // a compute pass's output (brdf_lut, equirect_to_cube, prefilter)
#define MIP_SRC_IMAGE 0          // mip_halve: level - 1 in, level out
#define MIP_DST_IMAGE 1
#define LIGHT_BUFFER_IMAGE 0     // deferred lighting's output
#define EDGE_GROUPS_IMAGE 1      // deferred lighting's edge groups

#endif
