// What the lighting reads from the GI probes (included by shaders/lighting/shading.glsl, which
// reflects it in shade_gi): irradiance of every bounce at a surface point.
#include "effects/gi/gi_sample.glsl"
