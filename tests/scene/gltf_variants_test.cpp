// glTF's KHR_materials_variants (host/scene/gltf_variants.h): a chosen
// variant gives each primitive its mapping's material, no choice keeps the
// primitives' own, and a malformed extension or a name the file does not
// declare is one line naming the file.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "input_error.h"
#include "scene/load.h"
#include "support/gltf_builder.h"
#include "support/temp_dir.h"

namespace {

using namespace vkpath;
using test::Json;

// Three diffuse materials (red, green, blue) and two triangles of material 0:
// the first maps variant "green" to material 1 and "blue" and "teal" to 2,
// the second maps nothing.
test::GltfBuilder variantsFile() {
    test::GltfBuilder b;
    for (const Json& colour : {Json{1, 0, 0, 1}, Json{0, 1, 0, 1}, Json{0, 0, 1, 1}})
        b.material(
            {{"pbrMetallicRoughness", {{"baseColorFactor", colour}, {"metallicFactor", 0}}}});
    b.node({{"mesh", b.triangle(0)}});
    b.node({{"mesh", b.triangle(0)}, {"translation", {2, 0, 0}}});
    b.camera();
    b.doc["extensionsUsed"] = {"KHR_materials_variants"};
    b.doc["extensions"]["KHR_materials_variants"]["variants"] = {
        {{"name", "green"}}, {{"name", "blue"}}, {{"name", "teal"}}};
    b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"] = {
        {{"material", 1}, {"variants", {0}}}, {{"material", 2}, {"variants", {1, 2}}}};
    return b;
}

std::vector<uint32_t> meshMaterials(const scene::Scene& s) {
    std::vector<uint32_t> materials;
    for (const scene::Mesh& mesh : s.meshes) materials.push_back(mesh.material);
    return materials;
}

TEST(GltfVariants, TheChosenVariantsMaterialsAndOtherwiseThePrimitivesOwn) {
    const test::TempDir dir;
    const auto path = variantsFile().writeGltf(dir / "variants.gltf");
    const test::Loaded own = test::load(path);
    EXPECT_EQ(own.scene.materialVariants, (std::vector<std::string>{"green", "blue", "teal"}));
    EXPECT_EQ(meshMaterials(own.scene), (std::vector<uint32_t>{0, 0}));
    EXPECT_EQ(own.warnings.find("KHR_materials_variants"), std::string::npos)
        << "a supported extension: " << own.warnings;
    for (const auto& [variant, first] :
         {std::pair{"green", 1u}, std::pair{"blue", 2u}, std::pair{"teal", 2u}}) {
        scene::LoadOptions options;
        options.materialVariant = variant;
        EXPECT_EQ(meshMaterials(test::load(path, options).scene), (std::vector<uint32_t>{first, 0}))
            << variant;
    }
}

TEST(GltfVariants, AnUnknownNameOrAMalformedExtensionIsOneLine) {
    const test::TempDir dir;
    scene::LoadOptions purple;
    purple.materialVariant = "purple";
    EXPECT_NE(test::loadError(variantsFile().writeGltf(dir / "a.gltf"), purple)
                  .find("no material variant named 'purple' (the file's: 'green', 'blue', 'teal')"),
              std::string::npos);

    test::GltfBuilder plain;
    plain.node({{"mesh", plain.triangle()}});
    EXPECT_NE(test::loadError(plain.writeGltf(dir / "plain.gltf"), purple)
                  .find("no material variants (KHR_materials_variants) to choose 'purple' from"),
              std::string::npos);

    const struct {
        const char* name;
        void (*spoil)(Json& doc);
        const char* says;
    } cases[] = {
        {"a material past the last",
         [](Json& d) {
             d["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][0]
              ["material"] = 3;
         },
         "mesh 0 primitive 0 mapping 0 material is not an index below 3"},
        {"a variant past the last",
         [](Json& d) {
             d["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][1]
              ["variants"] = {1, 3};
         },
         "mesh 0 primitive 0 mapping 1 variant is not an index below 3"},
        {"a fractional index",
         [](Json& d) {
             d["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][0]
              ["variants"] = {0.5};
         },
         "mapping 0 variant is not an index below 3"},
        {"a variant whose name is no string",
         [](Json& d) { d["extensions"]["KHR_materials_variants"]["variants"][1]["name"] = 5; },
         "variant 1 has no name"},
        {"two variants of one name",
         [](Json& d) {
             d["extensions"]["KHR_materials_variants"]["variants"][2]["name"] = "green";
         },
         "two variants are named 'green'"},
        {"mappings without variants declared",
         [](Json& d) { d["extensions"].erase("KHR_materials_variants"); },
         "mesh 0 primitive 0 maps variants the file does not declare"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        test::GltfBuilder b = variantsFile();
        c.spoil(b.doc);
        const std::string error = test::loadError(b.writeGltf(dir / "spoilt.gltf"));
        EXPECT_NE(error.find(c.says), std::string::npos) << error;
    }
}

TEST(GltfVariants, ColladaHasNone) {
    const test::TempDir dir;
    const auto path = dir / "scene.dae";
    test::writeText(path, "<COLLADA/>");
    scene::LoadOptions options;
    options.materialVariant = "green";
    try {
        scene::loadScene(path, options);
        ADD_FAILURE() << "loaded";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  path.string() +
                      ": no material variants to choose 'green' from: COLLADA has none (glTF's "
                      "KHR_materials_variants)");
    }
}

}  // namespace
