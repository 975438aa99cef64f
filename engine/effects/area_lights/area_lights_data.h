// The area-light effect's uniform block, shared by area_lights.cpp and the GLSL (gpu/gpu_block.h).
#ifndef CANDELA_AREA_LIGHTS_DATA_H
#define CANDELA_AREA_LIGHTS_DATA_H
#include "gpu/gpu_block.h"
#define AREA_LIGHTS_BINDING 5
#define AREA_POLYGONS_BINDING 7   // SSBO: one PolygonLight per emissive triangle or merged quad
#define LTC_MATRIX_UNIT 19        // RGBA32F: M^-1 entries, engine/effects/area_lights/ltc.hpp
#define LTC_AMPLITUDE_UNIT 20     // RG32F: (norm, fresnel)

GPU_NAMESPACE_BEGIN
GPU_BLOCK(AreaLightsData, AREA_LIGHTS_BINDING) {
    int method;         // 0: the pieces shade (arealight.method=pieces); 1: LTC polygons
    int polygon_count;  // PolygonLight entries (method 1)
    int ltc_size;       // the LTC table's side
    int residual;       // 1: the LTC's residual measured on cells of each polygon (arealight.residual)
    float far_field;    // a polygon farther than this many of its radii is shaded as a point (arealight.far_field; 0: never)
    float pad0;
    float pad1;
    float pad2;
} GPU_BLOCK_INSTANCE(area_lights);
GPU_BLOCK_CHECK(AreaLightsData, 32)

// One emissive triangle, or a convex quad of two coplanar triangles of the same radiance, as the
// lighting reads it: the element of the AREA_POLYGONS_BINDING buffer.
GPU_STRUCT(PolygonLight) {
    vec3 p0;             // world positions of the corners, in winding order
    float double_sided;  // 1 if the emitter is double-sided
    vec3 p1;
    float first_piece;   // the index of its emitter's first piece in the light buffer
    vec3 p2;
    float piece_count;   // its emitter's piece count
    vec3 radiance;       // emitted radiance (an emissive texture averaged over the polygon)
    float corners;       // 3 or 4 (p3 is used)
    vec3 p3;
    float pad0;
};
GPU_STRUCT_CHECK(PolygonLight, 80)
GPU_NAMESPACE_END

#endif
