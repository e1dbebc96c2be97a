// The glTF importer's instancing (scene::LoadOptions::instancing): a mesh that
// several nodes place is kept once, in its own space, with an instance per
// node (on; auto where the copies would add INSTANCING_MIN_TRIANGLES
// triangles or more), or copied into world space per node (off). Emissive
// meshes are copied whatever the option says, and the counts a scene is
// admitted by hold an instanced mesh once.
#include <gtest/gtest.h>

#include "scene/load.h"
#include "support/gltf_builder.h"
#include "support/temp_dir.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;

scene::LoadOptions with(scene::Instancing instancing) {
    scene::LoadOptions options;
    options.instancing = instancing;
    return options;
}

TEST(GltfInstancing, AMeshThreeNodesPlaceIsKeptOnceWhenOnAndCopiedWhenOff) {
    const test::TempDir dir;
    test::GltfBuilder b;
    const int triangle = b.triangle();
    b.node({{"mesh", triangle}, {"translation", {1, 0, 0}}});
    b.node({{"mesh", triangle}, {"scale", {2, 2, 2}}});
    b.node({{"mesh", triangle}, {"scale", {-1, 1, 1}}});  // a mirror
    b.camera();
    const fs::path file = b.writeGltf(dir / "three.gltf");

    const scene::Scene on = test::load(file, with(scene::Instancing::On)).scene;
    ASSERT_EQ(on.meshes.size(), 1u);
    EXPECT_TRUE(on.meshes[0].instanced);
    EXPECT_EQ(on.meshes[0].positions[1], glm::vec3(1, 0, 0));  // in its own space
    ASSERT_EQ(on.instances.size(), 3u);
    EXPECT_EQ(on.instances[0].objectToWorld[3], glm::dvec4(1, 0, 0, 1));
    EXPECT_EQ(on.instances[1].objectToWorld[0], glm::dvec4(2, 0, 0, 0));
    EXPECT_EQ(on.instances[2].objectToWorld[0], glm::dvec4(-1, 0, 0, 0));
    EXPECT_EQ(on.instances[1].meshCount, 1u);
    EXPECT_EQ(on.drawnTriangleCount(), 3u);
    EXPECT_EQ(on.triangleCount(), 1u);
    // The scene's box holds the placed copies.
    EXPECT_EQ(on.geometryBounds().lo.x, -1.0f);
    EXPECT_EQ(on.geometryBounds().hi.x, 2.0f);

    for (const auto instancing : {scene::Instancing::Off, scene::Instancing::Auto}) {
        const scene::Scene copied = test::load(file, with(instancing)).scene;
        EXPECT_TRUE(copied.instances.empty());
        ASSERT_EQ(copied.meshes.size(), 3u);
        EXPECT_FALSE(copied.meshes[0].instanced);
        EXPECT_EQ(copied.meshes[0].positions[0], glm::vec3(1, 0, 0));  // in the world
        EXPECT_EQ(copied.drawnTriangleCount(), 3u);
    }
}

TEST(GltfInstancing, AutoInstancesWhereTheCopiesWouldAddEnoughTriangles) {
    const test::TempDir dir;
    for (const int placements : {27, 28}) {
        test::GltfBuilder b;
        const int ball = b.uvSphere(100, false);  // 39 600 triangles
        for (int i = 0; i < placements; ++i)
            b.node({{"mesh", ball}, {"translation", {3 * i, 0, 0}}});
        b.camera();
        const fs::path file = b.writeGltf(dir / "balls.gltf");
        scene::GeometryCounts admitted;
        scene::LoadOptions options;
        options.admit = [&](const std::string&, const scene::GeometryCounts& c) { admitted = c; };
        const scene::Scene s = test::load(file, options).scene;
        // 27 balls: the copies add 1 029 600 triangles < 2^20; 28: 1 069 200.
        const bool instanced = uint64_t(placements - 1) * 39600 >= scene::INSTANCING_MIN_TRIANGLES;
        EXPECT_EQ(instanced, placements == 28);
        EXPECT_EQ(s.instances.size(), instanced ? size_t(placements) : 0u);
        EXPECT_EQ(s.meshes.size(), instanced ? 1u : size_t(placements));
        EXPECT_EQ(admitted.triangles, instanced ? 39600u : 39600u * placements);
        EXPECT_EQ(admitted.instances, instanced ? uint64_t(placements) : 0u);
        EXPECT_EQ(admitted.triangles, s.countGeometry().triangles);
        EXPECT_EQ(admitted.instances, s.countGeometry().instances);
    }
}

TEST(GltfInstancing, EmissiveMeshesAreCopiedAndEveryPrimitiveOfAMeshIsPlacedTogether) {
    const test::TempDir dir;
    test::GltfBuilder b;
    const int glow = b.material({{"emissiveFactor", {1, 1, 1}}});
    const int lamp = b.triangle(glow);
    const int two = b.triangle();
    // A second primitive of mesh `two`, with a material of its own.
    const int red = b.material({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}});
    test::Json second = b.doc["meshes"][size_t(two)]["primitives"][0];
    second["material"] = red;
    b.doc["meshes"][size_t(two)]["primitives"].push_back(second);
    for (int i = 0; i < 2; ++i) {
        b.node({{"mesh", lamp}, {"translation", {0, 2 * i, 0}}});
        b.node({{"mesh", two}, {"translation", {3, 2 * i, 0}}});
    }
    b.camera();
    const scene::Scene s =
        test::load(b.writeGltf(dir / "mixed.gltf"), with(scene::Instancing::On)).scene;
    size_t lamps = 0, instanced = 0;
    for (const scene::Mesh& m : s.meshes) {
        lamps += s.materials[m.material].emissive();
        instanced += m.instanced;
        EXPECT_NE(s.materials[m.material].emissive(), m.instanced);
    }
    EXPECT_EQ(lamps, 2u);      // copied
    EXPECT_EQ(instanced, 2u);  // mesh `two`'s two primitives, once
    ASSERT_EQ(s.instances.size(), 2u);
    EXPECT_EQ(s.instances[0].meshCount, 2u);
    EXPECT_EQ(s.instances[1].firstMesh, s.instances[0].firstMesh);
}

}  // namespace
