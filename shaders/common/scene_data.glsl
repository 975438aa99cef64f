// GPU layouts shared by the passes; the C++ side is engine/render/gpu_scene.hpp (the Frame block's
// size is checked against the GL in tests/unit/test_effects.cpp). Effects keep their own data in
// their own blocks (engine/effects/*/*_data.h).
#include "lights.glsl"

layout(std140, binding = 0) uniform Frame {
    mat4 view;
    mat4 proj;
    mat4 view_proj;
    mat4 inv_view_proj;
    vec4 camera_pos;       // xyz
    vec4 env_radiance;     // rgb: constant radiance, or the map's scale when w = 1 (a map is bound)
    vec4 env_sh[9];        // irradiance SH of the environment map (rgb), scaled
    ivec4 counts;          // x = lights in the light buffer (punctual first, then area-light
                           // pieces), y = env map mip count, z = punctual lights
    ivec4 debug;           // x view (0 radiance, 1 light visibility, 2 ssao), y light index
    vec4 viewport;         // width, height, 1/width, 1/height
    ivec4 view_flags;      // x 1 in the camera's view (screen-space effect buffers are valid), 0 in
                           // other views (reflection probe faces)
    vec4 depth_to_view;    // view z of a depth d: (x * d + y) / (z * d + w) (rows of the inverse projection)
    ivec4 env_mode;        // x 1: the static environment cube is bound
} frame;

struct MaterialData {
    vec4 base_color;
    vec4 emission_metallic;    // rgb emission (factor * strength), a metallic
    vec4 params;               // x roughness, y alpha cutoff, z alpha mode (0 opaque 1 mask 2 blend), w double sided
    vec4 specular;             // rgb specular color, a specular factor
    vec4 params2;              // x ior, y transmission, z normal scale, w occlusion strength
    ivec4 texcoord;            // texcoord set of base, metallic-roughness, normal, occlusion (-1: none)
    ivec4 texcoord2;           // x emissive (-1: none)
    vec4 uv_transform[10];     // per slot two rows of the 2x3 affine KHR_texture_transform
    vec4 volume;               // x thickness (0: thin-walled), yzw attenuation color
    vec4 volume2;              // x attenuation distance (0: none)
    ivec4 images;              // scene image of base, metallic-roughness, normal, occlusion (-1: none)
    ivec4 images2;             // x emissive image, y wrap modes for the ray tracer (4 bits per slot),
                               // z NEAREST magnification per slot for the ray tracer (1 bit per slot)
};

layout(std430, binding = 1) readonly buffer Materials { MaterialData materials[]; };
layout(std430, binding = 2) readonly buffer Lights { PunctualLight lights[]; };

// Irradiance from 9 SH coefficients (Ramamoorthi & Hanrahan 2001, eq. 13).
vec3 sh_irradiance(vec3 n) {
    const float c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    float x = n.x, y = n.y, z = n.z;
    return c1 * frame.env_sh[8].rgb * (x * x - y * y) + c3 * frame.env_sh[6].rgb * z * z +
           c4 * frame.env_sh[0].rgb - c5 * frame.env_sh[6].rgb +
           2.0 * c1 * (frame.env_sh[4].rgb * x * y + frame.env_sh[7].rgb * x * z + frame.env_sh[5].rgb * y * z) +
           2.0 * c2 * (frame.env_sh[3].rgb * x + frame.env_sh[1].rgb * y + frame.env_sh[2].rgb * z);
}
