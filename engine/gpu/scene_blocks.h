// The base's GPU data, declared once for C++ (engine/render/gpu_scene.hpp, renderer.cpp fill it)
// and GLSL (shaders/common/scene_data.glsl and lights.glsl read it), through gpu/gpu_block.h:
// the frame's uniform block, and the elements of the material and light storage buffers.
#ifndef CANDELA_GPU_SCENE_BLOCKS_H
#define CANDELA_GPU_SCENE_BLOCKS_H

#include "gpu/bindings.h"
#include "gpu/gpu_block.h"

// FrameData::debug_view: what the lighting writes instead of radiance (debug.view). Each shows
// one of the lighting's hook points (render/shading_hooks.hpp), whichever effects provide it.
#define DEBUG_VIEW_NONE 0
#define DEBUG_VIEW_VISIBILITY 1  // light debug_light's share reaching the point: the light_visibility hook
#define DEBUG_VIEW_OCCLUSION 2   // the occlusion hook (SSAO's buffer)
#define DEBUG_VIEW_INDIRECT 3    // the indirect_light hook (GI probes, RSM)

GPU_NAMESPACE_BEGIN

// The rasterizer's frame: camera, environment, light counts, debug view. Reflection probes draw
// their faces with their own copies (engine/effects/reflections/).
GPU_BLOCK(FrameData, FRAME_BINDING) {
    mat4 view;
    mat4 proj;
    mat4 view_proj;
    mat4 inv_view_proj;
    vec4 camera_pos;           // xyz
    vec3 env_radiance;         // constant radiance, or the map's scale when env_map_bound = 1
    float env_map_bound;       // 1: an environment map is bound (ENVIRONMENT_UNIT)
    vec4 env_sh[9];            // irradiance SH of the environment map (rgb), scaled
    int light_count;           // lights in the light buffer (punctual first, then area-light pieces)
    int env_mips;              // mip count of the environment (map, or the cube when bound)
    int punctual_light_count;
    float specular_filter;     // variance of the pixel filter specular lobes are widened by (0: none)
    int debug_view;            // DEBUG_VIEW_* (above)
    int debug_light;           // the light of the visibility view
    int camera_view;           // 1 in the camera's view (screen-space effect buffers are valid), 0 in
                               // other views (reflection probe faces)
    int env_cube_bound;        // 1: the static environment cube is bound (ENV_CUBE_UNIT)
    vec4 viewport;             // width, height, 1/width, 1/height
    vec4 depth_to_view;        // view z of a depth d: (x * d + y) / (z * d + w) (rows of the inverse projection)
} GPU_BLOCK_INSTANCE(frame);
GPU_BLOCK_CHECK(FrameData, 496)

// A material (std430, MATERIALS_BINDING; the draw's index selects it). Texture slots, in this
// order everywhere: 0 base colour, 1 metallic-roughness, 2 normal, 3 occlusion, 4 emissive.
GPU_STRUCT(MaterialData) {
    vec4 base_color;
    vec3 emission;             // factor * strength
    float metallic;
    float roughness;
    float alpha_cutoff;
    float alpha_mode;          // 0 opaque, 1 mask, 2 blend
    float double_sided;        // 1: double sided
    vec3 specular_color;
    float specular_factor;
    float ior;
    float transmission;
    float normal_scale;
    float occlusion_strength;
    ivec4 texcoord;            // texcoord set of slots 0-3 (-1: none)
    int emissive_texcoord;     // texcoord set of slot 4 (-1: none)
    int pad0;
    int pad1;
    int pad2;
    vec4 uv_transform[10];     // per slot two rows of the 2x3 affine KHR_texture_transform
    vec3 attenuation_color;    // KHR_materials_volume
    float thickness;           // 0: thin-walled
    float attenuation_distance;  // 0: no attenuation
    float pad3;
    float pad4;
    float pad5;
    ivec4 images;              // scene image of slots 0-3 (-1: none)
    int emissive_image;        // scene image of slot 4 (-1: none)
    int wrap_modes;            // for the ray tracer: 4 bits per slot, s then t (0 repeat, 1 clamp
                               // to edge, 2 mirrored repeat)
    int nearest_magnification; // for the ray tracer: 1 bit per slot, NEAREST magnification
    int pad6;
    vec4 clearcoat;            // x factor, y roughness, z coat normal scale; w 1: unlit (KHR_materials_unlit)
    vec4 sheen;                // rgb colour (0: no sheen), a roughness
    vec4 anisotropy;           // x strength, y cos and z sin of the rotation from the tangent, w 0
    vec4 iridescence;          // x factor, y film ior, z thickness minimum, w maximum (nanometres)
    ivec4 ext_image[3];        // scene image of extension texture slot s at [s / 4][s % 4] (-1: none)
    ivec4 ext_texcoord[3];     // texcoord set of slot s, the same way (-1: no texture)
    vec4 ext_uv_transform[24]; // per slot two rows of its 2x3 affine KHR_texture_transform
};
GPU_STRUCT_CHECK(MaterialData, 880)

// The extensions' texture slots (Material::ExtSlot), all read from the scene's image array at
// level 0 by the rasterizer and the tracer alike (shaders/common/material_ext.glsl).
#define EXT_SPECULAR 0               // specularTexture: A
#define EXT_SPECULAR_COLOR 1         // specularColorTexture: RGB, sRGB
#define EXT_TRANSMISSION 2           // transmissionTexture: R
#define EXT_THICKNESS 3              // thicknessTexture: G
#define EXT_CLEARCOAT 4              // clearcoatTexture: R
#define EXT_CLEARCOAT_ROUGHNESS 5    // clearcoatRoughnessTexture: G
#define EXT_CLEARCOAT_NORMAL 6       // clearcoatNormalTexture: RGB
#define EXT_SHEEN_COLOR 7            // sheenColorTexture: RGB, sRGB
#define EXT_SHEEN_ROUGHNESS 8        // sheenRoughnessTexture: A
#define EXT_ANISOTROPY 9             // anisotropyTexture: RG direction, B strength
#define EXT_IRIDESCENCE 10           // iridescenceTexture: R
#define EXT_IRIDESCENCE_THICKNESS 11 // iridescenceThicknessTexture: G
#define EXT_SLOT_COUNT 12

// A light (std430, LIGHTS_BINDING): KHR_lights_punctual lights, then the rasterizer's area-light
// pieces (shaders/common/lights.glsl).
GPU_STRUCT(LightData) {
    vec3 position;             // world
    float type;                // LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT, LIGHT_AREA_PATCH
    vec3 direction;            // where the light points to (patch: its normal)
    float range;               // 0: infinite
    vec3 color;                // color * intensity (patch: radiance * area, W/sr at normal incidence)
    float patch_area;          // patch: its area (bounds the 1/d^2 below the patch's size)
    float spot_scale;          // spot: 1 / (cos inner - cos outer)
    float spot_offset;         // spot: -cos outer * spot_scale
    float first_shadow_view;   // the light's first shadow view (engine/effects/shadows/), -1: none
    float shadow_view_count;
    float patch_two_sided;     // patch: 1 if it emits from both sides
    float cutoff;              // point/spot without a range: the raster's reach (lights.cutoff), 0: none
    float pad1;
    float pad2;
};
GPU_STRUCT_CHECK(LightData, 80)

GPU_NAMESPACE_END

#endif
