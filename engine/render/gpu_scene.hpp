#pragma once
// The Scene on the GPU: one vertex/index buffer for all primitives, material and light SSBOs,
// textures and samplers, and the environment. The GPU layouts are in gpu/scene_blocks.h.
#include <array>
#include <map>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "gl/handles.hpp"
#include "gpu/scene_blocks.h"
#include "image/image.hpp"
#include "platform/gl_worker.hpp"
#include "render/shadow_atlas.hpp"
#include "scene/animation.hpp"
#include "scene/scene.hpp"
#include "shader/shader_library.hpp"

namespace candela {

// The frame block and the material and light buffers' elements, declared with the GLSL.
using gpu::FrameData;
using gpu::LightData;
using gpu::MaterialData;

// Irradiance SH (9 RGB coefficients) of an equirectangular radiance map, projected with solid-angle
// weights; evaluated in shaders with Ramamoorthi & Hanrahan's formula.
std::array<glm::vec3, 9> project_irradiance_sh(const ImageF& equirect);

MaterialData to_gpu(const Material& material);
LightData to_gpu(const Scene::PlacedLight& light);

// What the shadow setup needs to know about each light of the light buffer.
struct LightInfo {
    enum class Kind { directional, point, spot, area };
    Kind kind = Kind::point;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // where the light points (area piece: its normal)
    float outer_cone = 0.0f;                  // spot, radians
    float size = 0.0f;                        // world units (area piece: sqrt of its area)
    int own_draw = -1;                        // an area piece's emitter: not drawn into its maps
    bool double_sided = false;                // an area piece that emits from both sides
    int first_view = -1, view_count = 0;      // shadow views, set by update_lights (their tiles: shadow_atlas())
};

// The rasterizer's area-light approximation: each emissive draw split into `samples` pieces of
// about equal area (recursive area-median splits of its triangles, refined into sub-triangles),
// each a one- or two-sided Lambertian emitter at the piece's centroid.
// The splitting is the area_lights effect's (effects/area_lights/area_pieces.cpp), which hands it
// to update_lights through LightSetup::split_emitters; update_lights appends the pieces to the
// light buffer in this layout.
struct AreaPiece {
    glm::vec3 centroid{0.0f};
    glm::vec3 normal{0.0f, -1.0f, 0.0f};
    float area = 0.0f;
    glm::vec3 power_per_sr{0.0f};  // emitted radiance * area (W/sr at normal incidence)
    bool double_sided = false;
    int draw = -1;
};

// The smallest change of linear radiance that can move the display (exposure 0, tonemap.glsl's
// ACES fit and sRGB) by one 8-bit step: 1/255 over the transform's steepest slope, 6.397 at
// radiance 0.0088 (where sRGB's linear segment meets the ACES toe; the test
// LightCutoff.DisplayQuantumIsOneStepAtTheSteepestSlope measures it).
inline constexpr float kDisplayQuantum = (1.0f / 255.0f) / 6.397f;
// The distance at which a point light of this peak intensity (W/sr, the largest channel) lights
// a white Lambertian surface at normal incidence with `fraction` of kDisplayQuantum, shared by
// `lights` lights: I / (pi d^2) = fraction * kDisplayQuantum / lights. Each light's cut then
// costs a point at most its share, and all of them together at most `fraction` of the quantum.
// 0 for a fraction <= 0 or no intensity (no cutoff).
float light_cutoff_distance(float peak_intensity, float fraction, int lights = 1);
// The cutoff distance of each of scene.placed_lights() (in that order) at lights.cutoff
// `fraction`: light_cutoff_distance for the point and spot lights without a range, sharing the
// fraction among them; 0 for the others (a range, or a directional light) and for all at 0.
std::vector<float> unranged_light_cutoffs(const Scene& scene, float fraction);

class GpuScene;
// Splits the scene's emissive draws into `samples` pieces each (an effect provides it).
using EmitterSplitter = std::vector<AreaPiece> (*)(const Scene& scene, const GpuScene& gpu, int samples);

class GpuScene {
public:
    struct Draw {
        int node;
        int primitive;           // index in the node's mesh
        int primitive_material;  // index into the material SSBO (default material appended last)
        GLsizei index_count;
        std::size_t first_index;
        GLint base_vertex;
        glm::mat4 model;
        glm::mat3 normal_matrix;
        bool mirrored;
        AlphaMode alpha_mode;
        bool double_sided;
        Bounds world_bounds;
        // The solid a transmitted ray crosses, for the raster's refraction through a solid
        // (not thin-walled) transmissive primitive: its box (1) or the ellipsoid inscribed in
        // its box (2) in mesh space, where the mesh is one (volume_shape); 0: neither.
        bool solid_transmissive = false;
        int volume_shape = 0;
        glm::vec3 volume_lo{0.0f}, volume_hi{0.0f};
        std::array<int, 5> textures;  // scene image per slot, -1 none
        std::array<bool, 5> srgb;
        std::array<SamplerDesc, 5> samplers;
        // Motion during the shutter (set_motion): the model matrix at shutter open and close, and
        // whether this draw moves at all (its matrix or, deformed, its vertices change).
        glm::mat4 model_open{1.0f}, model_close{1.0f};
        bool moves = false;
    };

    // 1 when every triangle of `p` lies on a face of its bounds (a box), 2 when every vertex lies on
    // the ellipsoid inscribed in them (within 2 % of its radii: a sphere or ellipsoid), else 0.
    // Deformable primitives: 0.
    static int volume_shape(const Primitive& p);

    // Throws candela::Error (bad_input) if the environment map cannot be read.
    // With a running `mips` worker (it must outlive this GpuScene), every texture the draws use
    // is uploaded here and its mipmaps generated on the worker's thread meanwhile; texture()
    // waits for them at the first draw. The texels are the same as without (gl::draw_mipmaps
    // equals glGenerateTextureMipmap's), only made sooner. The worker needs `shaders` for this.
    // With `shaders`, the environment map's mipmaps come from FloatMipmaps (render/environment.hpp:
    // the same texels, no blit compile); without, from glGenerateTextureMipmap.
    explicit GpuScene(const Scene& scene, GlWorker* mips = nullptr, const ShaderLibrary* shaders = nullptr);

    const std::vector<Draw>& draws() const { return draws_; }
    const Scene& scene() const { return scene_; }
    const gl::VertexArray& vertex_array() const { return vao_; }
    // The same vertices with a per-frame index buffer (triangle-sorted blending): write the
    // indices with upload_sorted_indices(), draw with first_index counted in that buffer.
    const gl::VertexArray& sorted_vertex_array() const { return sorted_vao_; }
    void upload_sorted_indices(const std::vector<std::uint32_t>& indices) {
        sorted_indices_.update(0, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)), indices.data());
    }
    const gl::Buffer& materials() const { return materials_; }
    // After select_variant() on the scene: every draw's material (its index, alpha mode, sides and
    // textures) from its primitive again. The material buffer holds every material of the file
    // already, so nothing is uploaded but textures a draw had not used yet (at its first frame).
    // Bumps pose_version(): the renderer then re-plans and its effects re-capture and retrace
    // (reflection probes, GI) as they do for a new pose.
    void refresh_materials();
    // Whether any material samples a texture (the shading programs leave texture code out otherwise).
    bool has_material_textures() const { return material_textures_; }
    // A material uses a layer of the glTF material extensions (clearcoat, sheen, anisotropy,
    // iridescence, unlit) or an extension's texture: programs then compile with MATERIAL_LAYERS
    // and the image array is bound for the rasterizer too (shaders/common/material_layers.glsl).
    bool has_material_layers() const { return material_layers_; }
    const gl::Buffer& lights() const { return lights_; }
    // Rebuilds the light buffer: punctual lights, then `area_samples` pieces per emissive draw;
    // with `shadows`, each light gets its shadow views (directional: `cascades`, spot: 1, point and
    // area piece: 6 cube faces) for at most `max_shadowed` lights, by priority: directional ones
    // first, then by peak intensity over the squared distance from `viewer` (when given; the
    // brightest without), which approximates what each light adds to the view. The views are tiles
    // of the shadow atlas (allocate_shadow_atlas): `shadow_resolution` texels at full resolution,
    // at most `shadow_budget_mb` MiB of layers. No-op if nothing changed.
    // `split`: what turns emitters into pieces (nullptr or area_samples 0: none).
    // `cutoff`: lights.cutoff, the reach of point and spot lights without a range
    // (light_cutoff_distance; 0: none).
    void update_lights(int area_samples, EmitterSplitter split, bool shadows, int cascades, int max_shadowed, float cutoff = 0.0f,
                       int shadow_resolution = 1024, double shadow_budget_mb = 512.0, const glm::vec3* viewer = nullptr);
    int light_count() const { return light_count_; }
    int punctual_light_count() const { return punctual_count_; }
    const std::vector<LightInfo>& light_infos() const { return light_infos_; }
    int shadow_view_count() const { return static_cast<int>(shadow_atlas_.tiles.size()); }
    // Where each shadow view lies in the shadow maps' array, and what the budget left out.
    const ShadowAtlas& shadow_atlas() const { return shadow_atlas_; }
    // Texture for a scene image, created on first use (sRGB or linear view of the same pixels).
    const gl::Texture& texture(int image, bool srgb);
    const gl::Sampler& sampler(const SamplerDesc& desc);
    const gl::Texture& white_texture() const { return white_; }

    // Every scene image resized to one size, as layers of an RGBA8 array (layer = image index):
    // how compute shaders (the ray tracer) sample material textures without bindless textures.
    // Level 0 only: the tracer reads no other.
    const gl::Texture& image_array() const;
    // The same storage as an sRGB view (colour textures decode before filtering).
    const gl::Texture& image_array_srgb() const;
    bool has_environment_map() const { return static_cast<bool>(env_map_); }
    // The map's pixels (linear RGBA, unscaled), for the ray tracer's importance sampling.
    const ImageF& environment_image() const { return env_image_; }
    const gl::Texture& environment_map() const { return env_map_ ? env_map_ : white_; }
    int environment_mips() const { return env_mips_; }
    glm::vec3 environment_radiance() const { return env_radiance_; }
    const std::array<glm::vec3, 9>& environment_sh() const { return env_sh_; }
    std::size_t triangle_count() const { return triangles_; }

    // Animation. After apply_pose() on the scene: re-uploads the deformable primitives'
    // vertices and updates every draw's model and normal matrix, mirroring and world bounds.
    // Returns whether anything changed (the renderer re-captures probes then).
    bool update_pose();
    // Motion during the shutter, for the raster motion blur: every vertex's object-space position
    // at shutter open and close, in the order of the main vertex buffer (so a draw's base_vertex
    // and the index buffer apply), and each draw's model_open/model_close. motion_vertex_array():
    // attribute 0 = position at open (vec3), 1 = at close, with the main index buffer.
    // clear_motion(): nothing moves (model_open = model_close = model).
    void set_motion(const Pose& open, const Pose& close);
    void clear_motion();
    bool has_motion() const { return has_motion_; }
    const gl::VertexArray& motion_vertex_array() const { return motion_vao_; }
    std::uint64_t pose_version() const { return pose_version_; }  // bumped by update_pose when something moved, and by refresh_materials
    std::uint64_t material_version() const { return material_version_; }  // bumped by refresh_materials

private:
    void set_material(Draw& d, const Primitive& p) const;
    struct Range { std::size_t first_index; GLint base_vertex; };
    std::vector<std::vector<Range>> ranges_;  // [mesh][primitive]
    // The posed vertices last uploaded of each deformable primitive ([mesh][primitive]; empty for
    // the others): update_pose uploads, and counts as a change, only what differs from them.
    std::vector<std::vector<std::vector<Vertex>>> uploaded_vertices_;
    gl::Buffer motion_;
    gl::VertexArray motion_vao_;
    bool has_motion_ = false;
    std::uint64_t pose_version_ = 0;
    std::uint64_t material_version_ = 0;
    std::size_t vertex_count_ = 0;
    const Scene& scene_;
    gl::Buffer vertices_, indices_, materials_, lights_, sorted_indices_;
    bool material_textures_ = false;
    bool material_layers_ = false;
    gl::VertexArray vao_, sorted_vao_;
    std::vector<Draw> draws_;
    int light_count_ = 0, punctual_count_ = 0;
    std::tuple<int, bool, int, int, float, int, double, bool, glm::vec3> light_key_{-1, false, 0, 0, 0.0f, 0, 0.0, false, glm::vec3(0.0f)};
    ShadowAtlas shadow_atlas_;
    std::vector<LightInfo> light_infos_;
    std::map<std::pair<int, bool>, gl::Texture> textures_;
    std::map<std::tuple<int, int, int, int>, gl::Sampler> samplers_;
    gl::Texture white_;
    gl::Texture env_map_;
    ImageF env_image_;
    mutable gl::Texture image_array_, image_array_srgb_;
    int env_mips_ = 1;
    glm::vec3 env_radiance_{0.0f};
    std::array<glm::vec3, 9> env_sh_{};
    std::size_t triangles_ = 0;
    // Mipmap jobs on the worker (constructor). Last member: destroyed first, waiting for the
    // jobs, before the textures they work on are deleted.
    GlWorker* mips_ = nullptr;
    gl::Program mip_program_;  // "mip_downsample", for the worker's jobs
    bool prefetching_ = false;
    struct PendingMips {
        std::map<std::pair<int, bool>, GlWorker::Ticket> textures;
        ~PendingMips() {
            for (auto& [key, ticket] : textures) try { GlWorker::wait(ticket); } catch (...) {}
        }
    };
    PendingMips pending_;
};

}  // namespace candela
