#include "../common/math.glsl"
// Cube-map texel directions in OpenGL's face convention (GL 4.5 core spec, table 8.19): face f
// in +X, -X, +Y, -Y, +Z, -Z order; (s, t) in [-1, 1] across the face, t growing with the row.
vec3 cube_direction(int face, vec2 st) {
    float s = st.x, t = st.y;
    vec3 d;
    if (face == 0) d = vec3(1.0, -t, -s);
    else if (face == 1) d = vec3(-1.0, -t, s);
    else if (face == 2) d = vec3(s, 1.0, t);
    else if (face == 3) d = vec3(s, -1.0, -t);
    else if (face == 4) d = vec3(s, -t, 1.0);
    else d = vec3(-s, -t, -1.0);
    return normalize(d);
}

// Texel (x, y) of a size x size face: its centre direction.
vec3 cube_texel_direction(int face, ivec2 texel, int size) {
    return cube_direction(face, (vec2(texel) + 0.5) / float(size) * 2.0 - 1.0);
}

// Van der Corput radical inverse in base 2: the second Hammersley coordinate.
float radical_inverse(uint bits) {
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return float(bits) * 2.3283064365386963e-10;
}
vec2 hammersley(uint i, uint n) { return vec2((float(i) + 0.5) / float(n), radical_inverse(i)); }

// A GGX-distributed half vector about +Z (Walter et al. 2007, eq. 35-36): pdf D(h) cos(theta_h).
vec3 sample_ggx_half(vec2 u, float alpha) {
    float phi = 2.0 * PI * u.y;
    float cos2 = (1.0 - u.x) / (1.0 + (alpha * alpha - 1.0) * u.x);
    float cos_t = sqrt(max(cos2, 0.0));
    float sin_t = sqrt(max(1.0 - cos2, 0.0));
    return vec3(sin_t * cos(phi), sin_t * sin(phi), cos_t);
}
