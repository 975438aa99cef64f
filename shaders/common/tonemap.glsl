// Display transform for PNG/screen output: exposure (EV), ACES filmic fit (Narkowicz 2015),
// sRGB encoding. The C++ twin is candela::tonemap_pixel (engine/image/tonemap.cpp).
vec3 aces_fit(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}
vec3 linear_to_srgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
vec3 display_transform(vec3 radiance, float exposure_ev) {
    return linear_to_srgb(aces_fit(max(radiance, vec3(0.0)) * exp2(exposure_ev)));
}
