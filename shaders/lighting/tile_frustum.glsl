// A screen tile's sub-frustum for light culling, shared by the deferred lighting
// (deferred/light.comp, with the tile's depth range) and the forward pass's tiles
// (forward/light_tiles.comp, without one).

vec3 tile_view_point(mat4 inv_proj, vec2 ndc, float depth) {
    vec4 p = inv_proj * vec4(ndc, depth, 1.0);
    return p.xyz / p.w;
}

// The tile [lo, hi] (NDC) between the reversed-Z depths `dnear` and `dfar`: its four side planes
// (inward normals, through a near edge and the far point behind it) and the view-space z of its
// far and near ends (negative).
void tile_frustum(mat4 inv_proj, vec2 lo, vec2 hi, float dnear, float dfar, out vec4 planes[4], out vec2 zrange) {
    vec3 n00 = tile_view_point(inv_proj, lo, dnear), n10 = tile_view_point(inv_proj, vec2(hi.x, lo.y), dnear);
    vec3 n01 = tile_view_point(inv_proj, vec2(lo.x, hi.y), dnear), n11 = tile_view_point(inv_proj, hi, dnear);
    vec3 f00 = tile_view_point(inv_proj, lo, dfar), f10 = tile_view_point(inv_proj, vec2(hi.x, lo.y), dfar);
    vec3 f01 = tile_view_point(inv_proj, vec2(lo.x, hi.y), dfar), f11 = tile_view_point(inv_proj, hi, dfar);
    vec3 centre = (n00 + n10 + n01 + n11 + f00 + f10 + f01 + f11) * 0.125;
    vec3 a[4] = vec3[4](n00, n10, n11, n01);
    vec3 b[4] = vec3[4](n01, n00, n10, n11);
    vec3 f[4] = vec3[4](f00, f10, f11, f01);
    for (int i = 0; i < 4; ++i) {
        vec3 nrm = normalize(cross(b[i] - a[i], f[i] - a[i]));
        if (dot(nrm, centre - a[i]) < 0.0) nrm = -nrm;
        planes[i] = vec4(nrm, -dot(nrm, a[i]));
    }
    zrange = vec2(min(f00.z, min(f10.z, min(f01.z, f11.z))), max(n00.z, max(n10.z, max(n01.z, n11.z))));
}

// Whether a point or spot light can reach the sub-frustum: conservative (a sphere of its reach
// that misses a side plane cannot); lights without a reach (and other types) always can.
bool light_meets_planes(LightData light, vec4 planes[4]) {
    int type = int(light.type);
    float range = light_reach(light);
    if ((type != LIGHT_POINT && type != LIGHT_SPOT) || range <= 0.0) return true;
    vec3 c = (frame.view * vec4(light.position, 1.0)).xyz;
    for (int i = 0; i < 4; ++i)
        if (dot(planes[i].xyz, c) + planes[i].w < -range) return false;
    return true;
}
