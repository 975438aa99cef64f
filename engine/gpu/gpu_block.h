// Blocks of GPU data declared once for C++ and GLSL. A header of blocks (engine/gpu/*.h, an
// effect's *_data.h) is included by the C++ that fills and uploads the struct and by the GLSL that
// reads it; C++ includes it by its path under engine/, and the shader library resolves the same
// path (ShaderLibrary looks up includes under engine/ too):
//
//   #include "gpu/gpu_block.h"
//   #define SSAO_BINDING 2
//   GPU_NAMESPACE_BEGIN
//   GPU_BLOCK(SsaoData, SSAO_BINDING) {
//       float radius; ...
//   } GPU_BLOCK_INSTANCE(ssao);
//   GPU_BLOCK_CHECK(SsaoData, 32)
//   GPU_NAMESPACE_END
//
// C++ sees `namespace candela::gpu { struct SsaoData { ... }; static_assert(...); }`, GLSL
// `layout(std140, binding = 2) uniform SsaoData { ... } ssao;`.
// The element of a storage buffer (an array of structs read as std430) is a GPU_STRUCT:
//
//   GPU_STRUCT(LightData) { vec3 position; float type; ... };
//   GPU_STRUCT_CHECK(LightData, 64)
//
// and the GLSL declares the buffer itself (`layout(std430, binding = LIGHTS_BINDING) readonly
// buffer Lights { LightData lights[]; };`), since C++ uploads arrays of the struct.
// Only members whose C++ layout equals std140's (and so std430's): int, uint, float, vec4, ivec4,
// mat4 and arrays of vec4, in groups of 16 bytes, and a vec3 or ivec3 only when one 4-byte scalar
// follows it in its group (std140 aligns a 3-vector to 16 bytes; glm to 4). No bool, no arrays of
// scalars.
// The C++ side asserts the size; tests/unit/test_effects.cpp checks each block's size against
// the GL's reflection.
//
// Units and bindings are named constants (#define, so that GLSL layouts can use them): the base's
// and the tracer's in gpu/bindings.h, an effect's in its *_data.h.
#ifndef CANDELA_GPU_BLOCK_H
#define CANDELA_GPU_BLOCK_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace candela::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec3 = glm::ivec3;
using ivec4 = glm::ivec4;
using mat4 = glm::mat4;
using uint = std::uint32_t;
}  // namespace candela::gpu
#define GPU_BLOCK(Type, b) struct Type
#define GPU_BLOCK_INSTANCE(instance)
#define GPU_BLOCK_CHECK(Type, bytes) static_assert(sizeof(Type) == (bytes) && sizeof(Type) % 16 == 0, #Type ": not the std140 size");
#define GPU_STRUCT(Type) struct Type
#define GPU_STRUCT_CHECK(Type, bytes) static_assert(sizeof(Type) == (bytes) && sizeof(Type) % 16 == 0, #Type ": not the std430 size");
#define GPU_NAMESPACE_BEGIN namespace candela::gpu {
#define GPU_NAMESPACE_END }
#else
#define GPU_BLOCK(Type, b) layout(std140, binding = b) uniform Type
#define GPU_BLOCK_INSTANCE(instance) instance
#define GPU_BLOCK_CHECK(Type, bytes)
#define GPU_STRUCT(Type) struct Type
#define GPU_STRUCT_CHECK(Type, bytes)
#define GPU_NAMESPACE_BEGIN
#define GPU_NAMESPACE_END
#endif

#endif
