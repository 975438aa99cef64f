// Uniform blocks declared once for C++ and GLSL. An effect's *_data.h is included by its C++
// (which fills and uploads the struct) and by its GLSL (which reads the block):
//
//   #include "effects/gpu_block.h"
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
// Only std140-safe members: int, uint, float in groups of four, vec4, ivec4, mat4 (no vec3, no
// bool, no arrays of scalars), so that the C++ layout equals std140; the C++ side asserts the
// size, and tests/unit/test_effects.cpp checks each block's size against the GL's reflection.
#ifndef CANDELA_GPU_BLOCK_H
#define CANDELA_GPU_BLOCK_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace candela::gpu {
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using mat4 = glm::mat4;
using uint = std::uint32_t;
}  // namespace candela::gpu
#define GPU_BLOCK(Type, b) struct Type
#define GPU_BLOCK_INSTANCE(instance)
#define GPU_BLOCK_CHECK(Type, bytes) static_assert(sizeof(Type) == (bytes) && sizeof(Type) % 16 == 0, #Type ": not the std140 size");
#define GPU_NAMESPACE_BEGIN namespace candela::gpu {
#define GPU_NAMESPACE_END }
#else
#define GPU_BLOCK(Type, b) layout(std140, binding = b) uniform Type
#define GPU_BLOCK_INSTANCE(instance) instance
#define GPU_BLOCK_CHECK(Type, bytes)
#define GPU_NAMESPACE_BEGIN
#define GPU_NAMESPACE_END
#endif

#endif
