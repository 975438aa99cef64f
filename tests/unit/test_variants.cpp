// KHR_materials_variants: SheenChair (tests/data/models/SheenChair, Khronos sample) loads its two
// variants and each primitive's mappings as the file documents them; select_variant switches
// the primitives' materials and back; bad mappings are bad input naming the JSON path; the
// renderer draws the selected variant (two variants differ, the default equals no selection).
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "reference_fixture.hpp"
#include "render/gpu_scene.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

Scene sheen_chair() { return load_gltf(fs::path(CANDELA_SOURCE_DIR) / "tests/data/models/SheenChair/SheenChair.gltf"); }

std::string material_name(const Scene& scene, int index) { return index < 0 ? "(default)" : scene.materials.at(static_cast<size_t>(index)).name; }

TEST(MaterialVariants, SheenChairMapsTheDocumentedMaterials) {
    Scene scene = sheen_chair();
    // extensions.KHR_materials_variants.variants of the file.
    ASSERT_EQ(scene.variants, (std::vector<std::string>{"Mango Velvet", "Peacock Velvet"}));
    EXPECT_EQ(scene.active_variant, -1);
    for (const std::string& what : scene.ignored) EXPECT_EQ(what.find("KHR_materials_variants"), std::string::npos) << what;
    // Two primitives carry mappings: the fabric and the wood; the metal and the label do not.
    int mapped = 0;
    for (const Mesh& m : scene.meshes)
        for (const Primitive& p : m.primitives) {
            if (p.variants.by_variant.empty()) continue;
            ++mapped;
            EXPECT_EQ(p.variants.by_variant.size(), 2u);
            EXPECT_EQ(p.material, p.variants.default_material) << "the default look before any selection";
        }
    EXPECT_EQ(mapped, 2);
    struct Expected {
        int variant;
        const char* fabric;
        const char* wood;
    };
    // The default is the file's `material` of each primitive (the Mango Velvet look).
    for (const Expected& e : {Expected{-1, "fabric Mystere Mango Velvet", "wood Brown"},
                              Expected{0, "fabric Mystere Mango Velvet", "wood Brown"},
                              Expected{1, "fabric Mystere Peacock Velvet", "wood Black"},
                              Expected{-1, "fabric Mystere Mango Velvet", "wood Brown"}}) {
        select_variant(scene, e.variant);
        EXPECT_EQ(scene.active_variant, e.variant);
        int fabric = -1, wood = -1, others = 0;
        for (const Mesh& m : scene.meshes)
            for (const Primitive& p : m.primitives) {
                if (p.variants.default_material == 0) fabric = p.material;
                else if (p.variants.default_material == 1) wood = p.material;
                else {
                    EXPECT_EQ(p.material, p.variants.default_material) << "an unmapped primitive keeps its material";
                    ++others;
                }
            }
        EXPECT_EQ(material_name(scene, fabric), e.fabric) << "variant " << e.variant;
        EXPECT_EQ(material_name(scene, wood), e.wood) << "variant " << e.variant;
        EXPECT_EQ(others, 2);
    }
    EXPECT_EQ(variant_changes(scene, 0), 0) << "Mango Velvet is the default look";
    EXPECT_EQ(variant_changes(scene, 1), 2);
}

TEST(MaterialVariants, FindVariantByNameOrIndexAndNamesTheChoicesOtherwise) {
    const Scene scene = sheen_chair();
    EXPECT_EQ(find_variant(scene, "Peacock Velvet"), 1);
    EXPECT_EQ(find_variant(scene, "0"), 0);
    EXPECT_EQ(find_variant(scene, "default"), -1);
    for (const char* bad : {"Teal Velvet", "2", "-1", ""}) {
        try {
            find_variant(scene, bad);
            ADD_FAILURE() << "'" << bad << "' was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::bad_input);
            const std::string what = e.what();
            EXPECT_NE(what.find("0 'Mango Velvet', 1 'Peacock Velvet'"), std::string::npos) << what;
        }
    }
    Scene copy = scene;
    EXPECT_THROW(select_variant(copy, 2), Error);
}

// A quad with two materials and a variant mapping, with `mapping` as the primitive's
// KHR_materials_variants object.
fs::path variant_file(const std::string& name, const nlohmann::json& mapping, int variants = 2) {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"name", "red"}}, {{"name", "blue"}}};
    const int mesh = b.add_quad_mesh(0);
    b.json()["meshes"][static_cast<size_t>(mesh)]["primitives"][0]["extensions"]["KHR_materials_variants"] = mapping;
    nlohmann::json list = nlohmann::json::array();
    for (int i = 0; i < variants; ++i) list.push_back({{"name", "v" + std::to_string(i)}});
    b.json()["extensions"]["KHR_materials_variants"] = {{"variants", list}};
    b.json()["extensionsUsed"] = {"KHR_materials_variants"};
    b.add_node({{"mesh", mesh}});
    return b.write(test::test_dir("variants_" + name), name);
}

void expect_bad_input(const fs::path& file, const std::string& needle) {
    try {
        load_gltf(file);
        ADD_FAILURE() << file << " loaded";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input);
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

TEST(MaterialVariants, BadMappingsAreBadInputNamingTheJsonPath) {
    // A valid file first (so that the failures below are the mappings' fault).
    const Scene ok = load_gltf(variant_file("ok", {{"mappings", {{{"material", 1}, {"variants", {1}}}}}}));
    ASSERT_EQ(ok.meshes.at(0).primitives.at(0).variants.by_variant, (std::vector<int>{PrimitiveVariants::kUnmapped, 1}));
    expect_bad_input(variant_file("variant", {{"mappings", {{{"material", 1}, {"variants", {2}}}}}}),
                     "meshes[0].primitives[0].extensions.KHR_materials_variants.mappings[0].variants[0]");
    expect_bad_input(variant_file("material", {{"mappings", {{{"material", 5}, {"variants", {0}}}}}}),
                     "meshes[0].primitives[0].extensions.KHR_materials_variants.mappings[0].material");
    expect_bad_input(variant_file("twice", {{"mappings", {{{"material", 1}, {"variants", {0}}}, {{"material", 0}, {"variants", {0}}}}}}),
                     "variant 0 is mapped twice");
}

class VariantRenderTest : public test::ReferenceTest {};

// The renderer draws the selected variant's materials: the two looks differ where the fabric and
// the wood are; the default after a selection is the render without any selection.
TEST_P(VariantRenderTest, VariantsChangeTheImageAndTheDefaultIsTheFilesLook) {
    Scene scene = sheen_chair();
    apply_lighting(scene, LightingMode::auto_select, scene.select_camera("", 1.0f));
    const ImageF plain = raster(scene, 96, 96, settings("", {}));
    select_variant(scene, 1);
    const ImageF peacock = raster(scene, 96, 96, settings("", {}));
    select_variant(scene, -1);
    const ImageF back = raster(scene, 96, 96, settings("", {}));
    // The chair covers much of the frame: Peacock's blue fabric and black wood change many pixels.
    size_t changed = 0;
    double max_back = 0.0;
    for (size_t i = 0; i < plain.pixels.size(); ++i) {
        changed += std::abs(plain.pixels[i] - peacock.pixels[i]) > 0.02f;
        max_back = std::max(max_back, static_cast<double>(std::abs(plain.pixels[i] - back.pixels[i])));
    }
    EXPECT_GT(changed, plain.pixels.size() / 20) << "variant 1 looks like the default";
    EXPECT_EQ(max_back, 0.0) << "the default after a selection differs from the file's look";
}

// The draws of a GpuScene made before a selection follow it with refresh_materials (the
// viewer's live switch), and then render as a GpuScene made after it.
TEST_P(VariantRenderTest, RefreshedDrawsRenderAsFreshOnes) {
    Scene scene = sheen_chair();
    apply_lighting(scene, LightingMode::auto_select, scene.select_camera("", 1.0f));
    GpuScene gpu(scene);
    select_variant(scene, 1);
    gpu.refresh_materials();
    Renderer renderer(lib_, scene, gpu, settings("", {}));
    renderer.render(scene.select_camera("", 1.0f), 96, 96);
    const ImageF live = renderer.read_radiance();
    EXPECT_EQ(count_nonfinite(live), 0u);
    const ImageF fresh = raster(scene, 96, 96, settings("", {}));
    double max_diff = 0.0;
    for (size_t i = 0; i < live.pixels.size(); ++i)
        max_diff = std::max(max_diff, static_cast<double>(std::abs(live.pixels[i] - fresh.pixels[i])));
    EXPECT_EQ(max_diff, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Backends, VariantRenderTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
