#pragma once
// The Scene: what a glTF file describes, in engine terms (docs/design.md, "Scene conventions").
// Plain data; the loader fills it, the renderer and the ray tracer read it.
#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace candela {

struct Bounds {
    glm::vec3 min{std::numeric_limits<float>::max()};
    glm::vec3 max{-std::numeric_limits<float>::max()};
    bool empty() const { return min.x > max.x; }
    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Bounds& b) {
        if (!b.empty()) extend(b.min), extend(b.max);
    }
    glm::vec3 center() const { return (min + max) * 0.5f; }
    glm::vec3 extent() const { return max - min; }
};

// Filtering and wrapping in glTF's numbers (which are the GL enums).
struct SamplerDesc {
    int mag_filter = 9729;  // GL_LINEAR
    int min_filter = 9987;  // GL_LINEAR_MIPMAP_LINEAR
    int wrap_s = 10497;     // GL_REPEAT
    int wrap_t = 10497;
};

// Decoded texture image, 8-bit RGBA. `valid == false`: missing or undecodable, drawn with the
// fallback checker so the problem is visible.
struct Image {
    std::string name;
    std::string uri;
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba8;
    bool valid = false;
};

struct TextureRef {
    int image = -1;  // index into Scene::images, -1: no texture
    SamplerDesc sampler;
    int texcoord = 0;  // 0 or 1
    // KHR_texture_transform as a 3x3 UV matrix (identity when absent).
    glm::mat3 transform{1.0f};
    float scale = 1.0f;  // normalTexture.scale or occlusionTexture.strength
    bool present() const { return image >= 0; }
};

enum class AlphaMode { opaque, mask, blend };

struct Material {
    std::string name = "default";
    glm::vec4 base_color{1.0f};
    float metallic = 1.0f;
    float roughness = 1.0f;
    glm::vec3 emissive{0.0f};
    float emissive_strength = 1.0f;  // KHR_materials_emissive_strength
    TextureRef base_color_texture, metallic_roughness_texture, normal_texture, occlusion_texture,
        emissive_texture;
    AlphaMode alpha_mode = AlphaMode::opaque;
    float alpha_cutoff = 0.5f;
    bool double_sided = false;
    // KHR_materials_specular: specular_factor 0 => pure Lambert.
    float specular_factor = 1.0f;
    glm::vec3 specular_color{1.0f};
    float ior = 1.5f;            // KHR_materials_ior
    float transmission = 0.0f;   // KHR_materials_transmission
    float thickness = 0.0f;      // KHR_materials_volume: > 0 solid refracting object, 0 thin-walled
    glm::vec3 attenuation_color{1.0f};
    float attenuation_distance = std::numeric_limits<float>::infinity();
    // KHR_materials_unlit: the base colour (times vertex colour and texture) is the radiance.
    bool unlit = false;
    // KHR_materials_clearcoat: a smooth dielectric coat (ior 1.5) over the material.
    float clearcoat = 0.0f;
    float clearcoat_roughness = 0.0f;
    // KHR_materials_sheen: a Charlie sheen lobe over the material (colour 0: none).
    glm::vec3 sheen_color{0.0f};
    float sheen_roughness = 0.0f;
    // KHR_materials_anisotropy: strength in [0, 1], rotation of the direction from the tangent
    // (radians, counter-clockwise in the tangent plane).
    float anisotropy = 0.0f;
    float anisotropy_rotation = 0.0f;
    // KHR_materials_iridescence: a thin film (thickness in nanometres) over the material.
    float iridescence = 0.0f;
    float iridescence_ior = 1.3f;
    float iridescence_thickness_min = 100.0f;
    float iridescence_thickness_max = 400.0f;

    // The extensions' textures, each read at the channel its extension names (MaterialExtSlot).
    enum ExtSlot {
        ext_specular,               // KHR_materials_specular specularTexture (A)
        ext_specular_color,         // specularColorTexture (RGB, sRGB)
        ext_transmission,           // KHR_materials_transmission transmissionTexture (R)
        ext_thickness,              // KHR_materials_volume thicknessTexture (G)
        ext_clearcoat,              // KHR_materials_clearcoat clearcoatTexture (R)
        ext_clearcoat_roughness,    // clearcoatRoughnessTexture (G)
        ext_clearcoat_normal,       // clearcoatNormalTexture (RGB tangent-space normal; scale)
        ext_sheen_color,            // KHR_materials_sheen sheenColorTexture (RGB, sRGB)
        ext_sheen_roughness,        // sheenRoughnessTexture (A)
        ext_anisotropy,             // KHR_materials_anisotropy anisotropyTexture (RG direction, B strength)
        ext_iridescence,            // KHR_materials_iridescence iridescenceTexture (R)
        ext_iridescence_thickness,  // iridescenceThicknessTexture (G)
        ext_slot_count
    };
    TextureRef ext_textures[ext_slot_count];
    // Uses a layer or an extension's texture (shaders compile MATERIAL_LAYERS for such scenes).
    bool has_layers() const {
        if (unlit || clearcoat > 0.0f || anisotropy > 0.0f || iridescence > 0.0f || glm::any(glm::greaterThan(sheen_color, glm::vec3(0.0f))))
            return true;
        for (const TextureRef& t : ext_textures)
            if (t.image >= 0) return true;
        return false;
    }

    glm::vec3 emission() const { return emissive * emissive_strength; }
    bool is_emissive() const { return glm::any(glm::greaterThan(emission(), glm::vec3(0.0f))); }
};

struct Vertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec4 tangent{1.0f, 0.0f, 0.0f, 1.0f};
    glm::vec2 uv0{0.0f};
    glm::vec2 uv1{0.0f};
    glm::vec4 color{1.0f};
};
static_assert(sizeof(Vertex) == 18 * sizeof(float), "Vertex is uploaded as-is");

// A morph target (glTF 2.0 section 3.7.2.2): per-vertex displacements, each array empty or one
// entry per vertex. Tangent deltas are xyz only (the handedness does not morph).
struct MorphTarget {
    std::vector<glm::vec3> position, normal, tangent;
};

// KHR_materials_variants on one primitive: the material the file gives it (`material`, the
// default look) and, per variant of Scene::variants, the material that variant maps it to
// (kUnmapped: the variant keeps the default). Empty `by_variant`: the primitive has no mappings.
struct PrimitiveVariants {
    static constexpr int kUnmapped = -2;
    int default_material = -1;
    std::vector<int> by_variant;
    // The material under `variant` (-1: the default look).
    int material(int variant) const {
        if (variant < 0 || static_cast<size_t>(variant) >= by_variant.size()) return default_material;
        const int m = by_variant[static_cast<size_t>(variant)];
        return m == kUnmapped ? default_material : m;
    }
};

struct Primitive {
    std::vector<Vertex> vertices;        // posed (animation.hpp pose_scene); rest pose for rigid ones
    std::vector<std::uint32_t> indices;  // always indexed (non-indexed input gets 0..n-1)
    int material = -1;                   // -1: the default material; the selected variant's (select_variant)
    PrimitiveVariants variants;          // KHR_materials_variants mappings
    Bounds bounds;                       // mesh space, of `vertices`
    // Deformation (skins, morph targets), empty for rigid primitives:
    // - rest: the vertices as the file gives them, before morphing and skinning; `vertices` is
    //   then the pose that pose_scene() computed from them (in the node's own space).
    // - joints/weights: `influence_sets` sets of 4 influences per vertex (JOINTS_n/WEIGHTS_n, n <
    //   influence_sets), vertex v's set k at [v * influence_sets + k]; joints index the node's
    //   skin's joint list. The loader normalises each vertex's weights to sum 1 (warning when a
    //   sum was off by more than 1e-3; all-zero weights bind to the node's own transform).
    // - targets: morph targets, as many as the mesh's weights.
    std::vector<Vertex> rest;
    std::vector<glm::u16vec4> joints;
    std::vector<glm::vec4> weights;
    int influence_sets = 0;
    std::vector<MorphTarget> targets;
    bool skinned() const { return influence_sets > 0; }
    bool deformable() const { return !rest.empty(); }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

struct Mesh {
    std::string name;
    std::vector<Primitive> primitives;
    std::vector<float> weights = {};  // default morph weights (one per target; zeros if the file has none)
};

// glTF skin (section 3.7.3): joint nodes and their inverse bind matrices (identity if absent).
struct Skin {
    std::string name;
    std::vector<int> joints;
    std::vector<glm::mat4> inverse_bind;  // one per joint
    int skeleton = -1;                    // informative only
};

// glTF animation (section 3.11). Keyframe times in seconds, strictly increasing (the loader
// rejects others). Values: `width` floats per keyframe element (3 translation/scale, 4 rotation
// quaternion xyzw, the morph target count for weights); CUBICSPLINE stores 3 elements per
// keyframe (in-tangent, value, out-tangent), as the file does.
enum class Interpolation { linear, step, cubic_spline };
enum class AnimationPath { translation, rotation, scale, weights };
struct AnimationSampler {
    std::vector<float> times;
    std::vector<float> values;
    int width = 3;
    Interpolation interpolation = Interpolation::linear;
};
struct AnimationChannel {
    int sampler = -1;
    int node = -1;
    AnimationPath path = AnimationPath::translation;
};
struct Animation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    float start = 0.0f;  // the earliest keyframe time of any sampler
    float end = 0.0f;    // the latest: the duration is `end` (glTF times start at 0)
};

enum class LightType { directional, point, spot };

struct Light {
    std::string name;
    LightType type = LightType::point;
    glm::vec3 color{1.0f};
    float intensity = 1.0f;  // radiometric: point/spot W/sr, directional W/m^2
    float range = 0.0f;      // 0: infinite
    float inner_cone = 0.0f;
    float outer_cone = 0.7853982f;
};

struct Camera {
    std::string name;
    bool orthographic = false;
    float yfov = 0.8f;          // radians
    float aspect_ratio = 0.0f;  // 0: use the image's
    float znear = 0.05f;
    float zfar = 0.0f;          // 0: infinite
    float xmag = 1.0f, ymag = 1.0f;
    int node = -1;  // the node that places it; -1 for the computed framing camera
    glm::mat4 world{1.0f};  // camera-to-world
    // Thin lens (depth of field): `aperture` is the lens RADIUS in scene units (0: a
    // pinhole, everything sharp); `focus_distance` the distance along the view axis that is in
    // focus, in scene units (0: not given; see with_lens in render/settings.hpp). From the glTF
    // camera's extras ("aperture", "focus_distance") or `--set camera.aperture=... `.
    float aperture = 0.0f;
    float focus_distance = 0.0f;
};

// A reflection probe declared on a node (`extras.reflection_probe`): captured at `position`; with
// an extent, lookups are box-projected (parallax-corrected) onto the axis-aligned box
// `center` +- `extent`. Position and center are in the node's space; extent is half sizes in
// world units along the world axes.
struct ReflectionProbe {
    glm::vec3 position{0.0f};
    glm::vec3 center{0.0f};
    glm::vec3 extent{0.0f};
    bool has_extent = false;
};

struct Node {
    std::string name;
    int parent = -1;
    std::vector<int> children;
    glm::mat4 local{1.0f};
    glm::mat4 world{1.0f};
    // The node's rest transform as translation, rotation, scale (what animation channels replace;
    // glTF forbids animating a node given by `matrix`, so `has_matrix` nodes keep `local`).
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 scale{1.0f};
    bool has_matrix = false;
    // `local` before the first apply_pose changed it: what nodes that the animation does not
    // move return to (set by apply_pose; scenes built in code may set only `local`).
    std::optional<glm::mat4> rest_local;
    int skin = -1;
    // Morph weights: `rest_weights` from the node (else the mesh's); `weights` the posed ones.
    std::vector<float> rest_weights;
    std::vector<float> weights;
    int mesh = -1;
    int camera = -1;
    int light = -1;
    std::optional<float> sphere_radius;  // extras.sphere.radius: exact sphere for the ray tracer
    std::optional<ReflectionProbe> reflection_probe;  // extras.reflection_probe
    bool mirrored() const { return glm::determinant(glm::mat3(world)) < 0.0f; }
};

struct ImageF;

struct Environment {
    glm::vec3 radiance{0.0f};  // constant environment
    std::filesystem::path map;  // equirectangular .hdr/.exr, empty if none
    // An equirectangular map made in memory (the default rig's sky); used instead of `map`.
    std::shared_ptr<const ImageF> image;
    std::string label;  // what `info` calls an in-memory map
    float intensity = 1.0f;
    bool has_map() const { return !map.empty() || image != nullptr; }
    bool present() const {
        return has_map() || glm::any(glm::greaterThan(radiance * intensity, glm::vec3(0.0f)));
    }
};

// What the loader had to repair (counted; each kind is also one warning).
struct SanitizeReport {
    int skipped_primitives = 0;     // non-triangle modes
    int generated_normals = 0;      // primitives
    int generated_tangents = 0;     // primitives
    int bad_normals = 0;            // zero-length or non-finite normals replaced
    int nonfinite_positions = 0;    // positions replaced by 0
    int missing_textures = 0;       // images that could not be loaded
};

// A world-space triangle, wound counter-clockwise seen from its front.
struct WorldTriangle {
    std::array<glm::vec3, 3> p;
    std::array<glm::vec3, 3> n;
    std::array<glm::vec2, 3> uv0, uv1;
    // World tangents; w is the handedness, already multiplied by the sign of the node's
    // determinant so that cross(n, t) * w is the world bitangent.
    std::array<glm::vec4, 3> tangent;
    int material = -1;
    int node = -1;
};

struct Scene {
    std::filesystem::path source;
    // Where the scene's coordinates start in the file's frame, in double: a scene far from the
    // file's origin is loaded next to it (gltf_loader_nodes.cpp), and everything the engine
    // computes is in float relative to this point. (0, 0, 0) for a scene near the origin.
    glm::dvec3 origin{0.0};
    // The file's placement of the roots in double, so that `origin` can move (scene/origin.hpp):
    // each root's translation, and each keyframe sampler that moves a root, as the file gives
    // them. Empty for a scene that never moved (move_origin then takes the scene as it is).
    struct RootPlacement {
        int node = -1;
        glm::dvec3 translation{0.0};  // in the file's frame
    };
    struct RootTrack {
        int animation = -1, channel = -1;
        int file_sampler = -1;   // the keyframes as the file gives them
        int moved_sampler = -1;  // their copy relative to `origin`, which the channel plays
    };
    std::vector<RootPlacement> root_placements;
    std::vector<RootTrack> root_tracks;
    std::vector<Node> nodes;
    std::vector<int> roots;
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Image> images;
    std::vector<Light> lights;
    std::vector<Camera> cameras;
    std::vector<Skin> skins;
    std::vector<Animation> animations;
    Environment environment;
    SanitizeReport sanitized;
    // glTF features in the file that Candela does not implement, one phrase each, e.g.
    // "KHR_materials_clearcoat on 4 materials", "TEXCOORD morph targets on 1 mesh". The loader also warns once each.
    std::vector<std::string> ignored;
    // KHR_materials_variants: the variant names in the file's order, and the selected one
    // (-1: every primitive has its default material). select_variant() switches.
    std::vector<std::string> variants;
    int active_variant = -1;

    const Material& material(int index) const;
    // Recomputes every node's world matrix from the hierarchy.
    void update_world_transforms();
    Bounds world_bounds() const;
    std::size_t triangle_count() const;  // instanced: counted per node that draws the mesh
    // All triangles in world space: positions by the node's world matrix, normals by its inverse
    // transpose, winding flipped under a mirroring (negative determinant) transform.
    std::vector<WorldTriangle> world_triangles() const;

    // Lights placed in the world (position, direction = the node's -Z axis).
    struct PlacedLight {
        const Light* light;
        glm::vec3 position;
        glm::vec3 direction;
    };
    std::vector<PlacedLight> placed_lights() const;

    // The camera to render from: glTF camera by index or name (throws bad_input if unknown);
    // an empty selector picks the first camera, else a framing camera from the bounds; "auto" is
    // always the framing camera.
    Camera select_camera(const std::string& selector, float image_aspect) const;
};

// KHR_materials_variants. find_variant: a variant by index or name ("default" or "none": -1,
// the file's own materials); throws bad_input naming the available variants otherwise.
// select_variant: sets every primitive's material to the variant's (-1: the defaults); an
// index out of range throws bad_input. variant_changes: how many primitives (counted per mesh,
// not per instance) the variant gives another material than their default.
int find_variant(const Scene& scene, const std::string& selector);
void select_variant(Scene& scene, int variant);
int variant_changes(const Scene& scene, int variant);

// A camera that frames `bounds` from the front (+Z side), slightly above.
Camera framing_camera(const Bounds& bounds);
glm::mat4 projection_matrix(const Camera& camera, float image_aspect);  // reversed-Z, [0,1] depth

// Depth of field, shared by the tracer and the raster approximation so both focus at
// the same distance:
// - has_thin_lens: aperture > 0 on a perspective camera. Orthographic cameras have no depth of
//   field: their aperture is ignored (the loader and the tracer warn), they stay pinhole-sharp.
// - focus_distance_or_auto: the camera's focus_distance when > 0, else AUTO: the distance along
//   the view axis (the camera's -Z) from the camera to the centre of `scene_bounds`, clamped to
//   >= znear (a centre behind the camera focuses at znear); an empty scene focuses at
//   max(znear, 1). The focal plane is the plane perpendicular to the view axis at that distance
//   (not a sphere around the camera).
bool has_thin_lens(const Camera& camera);
float focus_distance_or_auto(const Camera& camera, const Bounds& scene_bounds);

}  // namespace candela
