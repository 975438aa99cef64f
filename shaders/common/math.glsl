// Constants and small helpers shared by raster and ray-tracing shaders.
const float PI = 3.14159265358979323846;
const float INV_PI = 0.31830988618379067154;
// Rec. 709 luminance of linear RGB.
const vec3 LUMINANCE_WEIGHTS = vec3(0.2126, 0.7152, 0.0722);

float saturate(float x) { return clamp(x, 0.0, 1.0); }
vec3 saturate(vec3 x) { return clamp(x, vec3(0.0), vec3(1.0)); }
float pow5(float x) { float x2 = x * x; return x2 * x2 * x; }

// Equirectangular mapping used for environment maps: +Y up, u = 0.5 at -Z.
vec2 direction_to_equirect(vec3 d) {
    float u = 0.5 + atan(d.x, -d.z) * (0.5 * INV_PI);
    float v = acos(clamp(d.y, -1.0, 1.0)) * INV_PI;
    return vec2(u, v);
}
