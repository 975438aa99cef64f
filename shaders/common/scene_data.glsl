// The base's GPU data for the passes: the frame block and the material and light buffers, declared
// with the C++ in engine/gpu/scene_blocks.h (sizes checked against the GL in
// tests/unit/test_effects.cpp). Effects keep their own data in their own blocks
// (engine/effects/*/*_data.h).
#include "lights.glsl"

#include "gpu/scene_blocks.h"

layout(std430, binding = MATERIALS_BINDING) readonly buffer Materials { MaterialData materials[]; };
layout(std430, binding = LIGHTS_BINDING) readonly buffer Lights { LightData lights[]; };

// Irradiance from 9 SH coefficients (Ramamoorthi & Hanrahan 2001, eq. 13).
vec3 sh_irradiance(vec3 n) {
    const float c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    float x = n.x, y = n.y, z = n.z;
    return c1 * frame.env_sh[8].rgb * (x * x - y * y) + c3 * frame.env_sh[6].rgb * z * z +
           c4 * frame.env_sh[0].rgb - c5 * frame.env_sh[6].rgb +
           2.0 * c1 * (frame.env_sh[4].rgb * x * y + frame.env_sh[7].rgb * x * z + frame.env_sh[5].rgb * y * z) +
           2.0 * c2 * (frame.env_sh[3].rgb * x + frame.env_sh[1].rgb * y + frame.env_sh[2].rgb * z);
}
