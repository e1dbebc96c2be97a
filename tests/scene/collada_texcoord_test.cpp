// COLLADA texture coordinates: a TEXCOORD input becomes Mesh::texcoords0 with v
// flipped to glTF's top-left origin (v = 1 - t), vertices split where a
// position has several texture coordinates (seams), and bad coordinates are
// one error line. The duck of Debian's assimp-testmodels is a file made by
// others (tools/install-deps installs it).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "input_error.h"
#include "scene/collada_loader.h"
#include "support/temp_dir.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;
using test::TempDir;

const fs::path DUCK = "/usr/share/assimp/models/Collada/duck.dae";

// A unit square in z = 0 as two triangles of a polylist, each corner with a
// TEXCOORD index (`uvIndices`, 6 of them) into `uvs` (5 s t pairs).
std::string squareDocument(const std::string& uvs, const std::vector<int>& uvIndices) {
    const std::vector<int> positions = {0, 1, 2, 0, 2, 3};
    std::string p;
    for (size_t k = 0; k < positions.size(); ++k)
        p += std::to_string(positions[k]) + " " + std::to_string(uvIndices[k]) + " ";
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Y_UP</up_axis></asset>
  <library_geometries><geometry id="square" name="square"><mesh>
    <source id="positions"><float_array id="positions-array" count="12">
      0 0 0  1 0 0  1 1 0  0 1 0</float_array>
      <technique_common><accessor source="#positions-array" count="4" stride="3"/>
      </technique_common></source>
    <source id="uvs"><float_array id="uvs-array">)" +
           uvs + R"(</float_array>
      <technique_common><accessor source="#uvs-array" count="5" stride="2">
        <param name="S" type="float"/><param name="T" type="float"/></accessor>
      </technique_common></source>
    <vertices id="vertices"><input semantic="POSITION" source="#positions"/></vertices>
    <polylist count="2">
      <input semantic="VERTEX" source="#vertices" offset="0"/>
      <input semantic="TEXCOORD" source="#uvs" offset="1" set="0"/>
      <vcount>3 3</vcount><p>)" +
           p + R"(</p>
    </polylist>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="Scene">
    <node id="Square" name="Square"><instance_geometry url="#square"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
}

scene::Scene loadQuiet(const fs::path& path) {
    std::vector<std::string> warnings;
    testing::internal::CaptureStderr();
    try {
        scene::Scene s = scene::loadCollada(path, {}, &warnings);
        testing::internal::GetCapturedStderr();
        return s;
    } catch (...) {
        testing::internal::GetCapturedStderr();
        throw;
    }
}

TEST(ColladaTexCoords, TheDucksCoordinatesArePerVertexInTheUnitSquare) {
    ASSERT_TRUE(fs::exists(DUCK)) << DUCK << " is missing: run tools/install-deps";
    const scene::Scene s = loadQuiet(DUCK);
    ASSERT_EQ(s.meshes.size(), 1u);
    const scene::Mesh& duck = s.meshes[0];
    EXPECT_EQ(duck.triangles.size(), 4212u);
    ASSERT_FALSE(duck.texcoords0.empty());
    EXPECT_EQ(duck.texcoords0.size(), duck.positions.size());
    EXPECT_TRUE(duck.texcoords1.empty());
    for (const glm::vec2& uv : duck.texcoords0) {
        EXPECT_GE(uv.x, 0.0f);
        EXPECT_LE(uv.x, 1.0f);
        EXPECT_GE(uv.y, 0.0f);
        EXPECT_LE(uv.y, 1.0f);
    }
}

TEST(ColladaTexCoords, TRunsUpSoVIsOneMinusT) {
    TempDir dir;
    const std::string text = squareDocument("0 0  1 0  1 1  0 1  0.25 0.125", {0, 1, 2, 0, 2, 3});
    const scene::Scene s = loadQuiet(dir.write("square.dae", text));
    ASSERT_EQ(s.meshes.size(), 1u);
    const scene::Mesh& m = s.meshes[0];
    ASSERT_EQ(m.positions.size(), 4u);  // every position has one coordinate: shared
    ASSERT_EQ(m.texcoords0.size(), 4u);
    for (size_t i = 0; i < m.positions.size(); ++i) {
        // The square's coordinates equal its positions' x and y (t up): v = 1 - y.
        EXPECT_FLOAT_EQ(m.texcoords0[i].x, m.positions[i].x);
        EXPECT_FLOAT_EQ(m.texcoords0[i].y, 1.0f - m.positions[i].y);
    }
}

TEST(ColladaTexCoords, APositionWithTwoCoordinatesBecomesTwoVertices) {
    TempDir dir;
    // Corner 0 of the second triangle takes coordinate 4 (0.25, 0.125): a seam.
    const std::string text = squareDocument("0 0  1 0  1 1  0 1  0.25 0.125", {0, 1, 2, 4, 2, 3});
    const scene::Scene s = loadQuiet(dir.write("seam.dae", text));
    const scene::Mesh& m = s.meshes.at(0);
    ASSERT_EQ(m.positions.size(), 5u);
    ASSERT_EQ(m.texcoords0.size(), 5u);
    ASSERT_EQ(m.triangles.size(), 2u);
    const uint32_t first = m.triangles[0].x, second = m.triangles[1].x;
    EXPECT_NE(first, second);
    EXPECT_EQ(m.positions[first], m.positions[second]);
    EXPECT_EQ(m.texcoords0[first], glm::vec2(0.0f, 1.0f));
    EXPECT_EQ(m.texcoords0[second], glm::vec2(0.25f, 0.875f));

    // Coordinate 4 equal to coordinate 0: one vertex again (exporters give
    // every corner a coordinate of its own, most of them equal).
    const scene::Scene same = loadQuiet(
        dir.write("same.dae", squareDocument("0 0  1 0  1 1  0 1  0 0", {0, 1, 2, 4, 2, 3})));
    EXPECT_EQ(same.meshes.at(0).positions.size(), 4u);
    EXPECT_EQ(same.meshes.at(0).triangles[0].x, same.meshes.at(0).triangles[1].x);
}

std::string loadError(const fs::path& path) {
    try {
        loadQuiet(path);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << path << " loaded without an error";
    return {};
}

TEST(ColladaTexCoords, BadCoordinatesAreOneErrorLine) {
    TempDir dir;
    const fs::path range =
        dir.write("range.dae", squareDocument("0 0  1 0  1 1  0 1  0 0", {0, 1, 2, 0, 2, 7}));
    const std::string outOfRange = loadError(range);
    EXPECT_EQ(outOfRange.rfind(range.string() + ": ", 0), 0u) << outOfRange;
    EXPECT_NE(outOfRange.find("TEXCOORD index 7 out of range"), std::string::npos) << outOfRange;

    const fs::path nan =
        dir.write("nan.dae", squareDocument("0 0  1 0  nan 1  0 1  0 0", {0, 1, 2, 0, 2, 3}));
    const std::string notFinite = loadError(nan);
    EXPECT_NE(notFinite.find("source 'uvs'"), std::string::npos) << notFinite;
    EXPECT_NE(notFinite.find("not finite"), std::string::npos) << notFinite;
}

}  // namespace
