// Vertex stage of lighting/surface.glsl: the texture coordinates of every material texture slot,
// with the slot's texcoord set and its KHR_texture_transform applied here, per vertex, and the
// material bits the fragment stage branches on around its texture reads. Expects
// common/scene_data.glsl; the fragment side of these varyings is in lighting/surface.glsl.
//
// Why per vertex and not per fragment: the mip level of texture() comes from the derivatives of
// the UV across a 2x2 quad, which includes helper invocations (quad lanes outside the triangle)
// at every triangle edge. Mesa's llvmpipe (22.3) does not execute SSBO loads for helper lanes:
// they read 0. Measured on BoxTextured: fwidth(materials[u_material].uv_transform[0].x), the
// identity's 1, is nonzero on 1156 edge pixels, and fwidth of that value minus
// (gl_HelperInvocation ? 0 : 1) is 0 on all of them; a value read from a UBO has fwidth 0
// everywhere. The transform used to be read from the materials SSBO per fragment, so
// the helper lanes computed uv = 0, the quad's UV derivative was about as large as the UV itself
// and texture() picked the smallest mip: 2x2 speckle along every triangle edge. Varyings are
// interpolated for helper lanes too, and a transform that is affine in the UV commutes with the
// (perspective-correct) interpolation, so the transformed UV can be computed per vertex, where
// every invocation is real. The same holds for the flat material bits.
layout(location = 2) uniform int u_material;

layout(location = 3) out vec4 v_slot_uv01;  // xy base colour, zw metallic-roughness
layout(location = 5) out vec4 v_slot_uv23;  // xy normal, zw occlusion
layout(location = 6) out vec2 v_slot_uv4;   // emissive
// Bits 0-4: slot has a texture (base colour, metallic-roughness, normal, occlusion, emissive);
// bit 5: alpha mode MASK.
layout(location = 7) flat out int v_material_bits;
// 1, interpolated as the other inputs are: lighting/surface.glsl divides every centroid input by it.
layout(location = 8) out float v_one;
// The raw texture coordinates, for the material extensions' textures (common/material_layers.glsl,
// read at level 0: no derivatives, so the helper lanes do not matter there).
layout(location = 9) out vec4 v_uv01;

vec2 material_slot_uv(MaterialData m, int slot, int set, vec2 uv0, vec2 uv1) {
    vec3 uv = vec3(set == 1 ? uv1 : uv0, 1.0);
    return vec2(dot(m.uv_transform[slot * 2].xyz, uv), dot(m.uv_transform[slot * 2 + 1].xyz, uv));
}

void write_material_uvs(vec2 uv0, vec2 uv1) {
    MaterialData m = materials[u_material];
    int sets[5] = int[5](m.texcoord.x, m.texcoord.y, m.texcoord.z, m.texcoord.w, m.emissive_texcoord);
    vec2 uv[5];
    int bits = int(m.alpha_mode) == 1 ? 32 : 0;
    for (int s = 0; s < 5; ++s) {
        uv[s] = sets[s] >= 0 ? material_slot_uv(m, s, sets[s], uv0, uv1) : uv0;
        if (sets[s] >= 0) bits |= 1 << s;
    }
    v_slot_uv01 = vec4(uv[0], uv[1]);
    v_slot_uv23 = vec4(uv[2], uv[3]);
    v_slot_uv4 = uv[4];
    v_material_bits = bits;
    v_uv01 = vec4(uv0, uv1);
    // Always 1, but not a constant to the compiler: Mesa folds a constant output into the
    // fragment stage, which then interpolates nothing.
    v_one = gl_VertexID >= 0 ? 1.0 : 2.0;
}
