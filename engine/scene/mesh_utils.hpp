#pragma once
#include "scene/scene.hpp"

namespace candela {

// Face normals, each triangle's vertices unshared first (the glTF rule for missing normals).
void generate_flat_normals(Primitive& primitive);
// Area-weighted average of face normals over shared vertices.
void generate_smooth_normals(Primitive& primitive);
// Per-vertex tangents from UV gradients (Lengyel 2001), Gram-Schmidt against the normal,
// handedness in w (bitangent = cross(normal, tangent) * w points to decreasing v, as glTF's
// normal maps expect). Vertices with degenerate UVs get any vector perpendicular to the normal.
void generate_tangents(Primitive& primitive, int texcoord);
// Replaces zero-length or non-finite normals by the face normal; returns how many.
int repair_normals(Primitive& primitive);
void compute_bounds(Primitive& primitive);

}  // namespace candela
