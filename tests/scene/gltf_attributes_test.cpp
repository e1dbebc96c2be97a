// The glTF vertex attributes beyond POSITION and NORMAL: TEXCOORD_0/1,
// COLOR_0 and TANGENT in each encoding glTF 2.0 (3.7.2.1) allows, the
// quantized ones of KHR_mesh_quantization, tangents under a mirroring
// transform, and each kind of bad attribute. Values are worked out by hand
// from glTF's normalization rules (3.11): c / 255, c / 65535, max(c / 127, -1).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "support/gltf_builder.h"
#include "support/temp_dir.h"

namespace {

using namespace vkpath;
using test::F32;
using test::GltfBuilder;
using test::Json;
using test::load;
using test::Loaded;
using test::loadError;
using test::TempDir;
using test::U16;
using test::U8;

constexpr int I8 = 5120, I16 = 5122;

// A 3-vertex accessor of `type` from raw little-endian bytes, with its
// bufferView strided to a multiple of 4 as glTF requires of vertex data.
template <typename T>
int attribute(GltfBuilder& g, const std::vector<T>& values, int componentType, const char* type,
              size_t width, bool normalized) {
    const size_t element = width * sizeof(T), stride = (element + 3) / 4 * 4;
    std::vector<uint8_t> bytes(stride * (values.size() / width), 0);
    for (size_t i = 0; i < values.size(); ++i)
        std::memcpy(&bytes[(i / width) * stride + (i % width) * sizeof(T)], &values[i], sizeof(T));
    const int view = g.view(bytes.data(), bytes.size(), stride == element ? 0 : stride);
    const int accessor = g.accessor(view, componentType, type, values.size() / width);
    if (normalized) g.doc["accessors"][accessor]["normalized"] = true;
    return accessor;
}

// The triangle (0,0,0) (1,0,0) (0,1,0) facing +Z with a +Z normal, as mesh 0
// on a node with `node`'s transform; attributes are added to its primitive.
struct Triangle {
    GltfBuilder g;
    int mesh;

    explicit Triangle(Json node = Json::object()) {
        mesh = g.triangle();
        node["mesh"] = mesh;
        node["name"] = "tri";
        g.node(node);
        g.camera();
    }
    void add(const char* name, int accessor) {
        g.doc["meshes"][mesh]["primitives"][0]["attributes"][name] = accessor;
    }
    void useQuantization() {
        g.doc["extensionsUsed"] = Json::array({"KHR_mesh_quantization"});
        g.doc["extensionsRequired"] = Json::array({"KHR_mesh_quantization"});
    }
};

// The first mesh of the file, by value: the loaded scene is a temporary.
scene::Mesh firstMesh(const std::filesystem::path& path) {
    return load(path).scene.meshes.at(0);
}

void expectNear(const glm::vec4& a, const glm::vec4& b, float tolerance = 1e-6f) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(a[c], b[c], tolerance) << "component " << c;
}

TEST(GltfAttributes, AbsentAttributesLeaveTheVectorsEmpty) {
    TempDir dir;
    Triangle t;
    const scene::Mesh m = firstMesh(t.g.writeGltf(dir / "plain.gltf"));
    EXPECT_TRUE(m.texcoords0.empty());
    EXPECT_TRUE(m.texcoords1.empty());
    EXPECT_TRUE(m.colors.empty());
    EXPECT_TRUE(m.tangents.empty());
}

TEST(GltfAttributes, FloatTexCoordsAndColoursAreKeptAsGiven) {
    TempDir dir;
    Triangle t;
    // UVs outside [0, 1] are legal (wrapping); glTF's v runs down, kept so.
    t.add("TEXCOORD_0", attribute<float>(t.g, {0, 0, 1, 0, 0.25f, -1.5f}, F32, "VEC2", 2, false));
    t.add("TEXCOORD_1", attribute<float>(t.g, {2, 3, 4, 5, 6, 7}, F32, "VEC2", 2, false));
    t.add("COLOR_0",
          attribute<float>(t.g, {1, 0, 0, 0.5f, 0, 1, 0, 1, 0, 0, 1, 0}, F32, "VEC4", 4, false));
    const Loaded loaded = load(t.g.writeGltf(dir / "float.gltf"));
    EXPECT_EQ(loaded.warnings, "");
    const scene::Mesh& m = loaded.scene.meshes.at(0);
    ASSERT_EQ(m.texcoords0.size(), 3u);
    EXPECT_EQ(m.texcoords0[1], glm::vec2(1, 0));
    EXPECT_EQ(m.texcoords0[2], glm::vec2(0.25f, -1.5f));
    ASSERT_EQ(m.texcoords1.size(), 3u);
    EXPECT_EQ(m.texcoords1[2], glm::vec2(6, 7));
    ASSERT_EQ(m.colors.size(), 3u);
    EXPECT_EQ(m.colors[0], glm::vec4(1, 0, 0, 0.5f));
    EXPECT_EQ(m.colors[2], glm::vec4(0, 0, 1, 0));
}

TEST(GltfAttributes, NormalizedUnsignedTexCoordsAndRgbColours) {
    TempDir dir;
    Triangle t;
    t.add("TEXCOORD_0", attribute<uint8_t>(t.g, {0, 255, 128, 51, 255, 0}, U8, "VEC2", 2, true));
    t.add("TEXCOORD_1",
          attribute<uint16_t>(t.g, {0, 65535, 32768, 13107, 1, 0}, U16, "VEC2", 2, true));
    // VEC3 colours are opaque: alpha 1.
    t.add("COLOR_0",
          attribute<uint16_t>(t.g, {65535, 0, 0, 0, 32768, 0, 0, 0, 13107}, U16, "VEC3", 3, true));
    const scene::Mesh m = firstMesh(t.g.writeGltf(dir / "normalized.gltf"));
    ASSERT_EQ(m.texcoords0.size(), 3u);
    EXPECT_EQ(m.texcoords0[0], glm::vec2(0.0f, 1.0f));
    EXPECT_NEAR(m.texcoords0[1].x, 128.0f / 255.0f, 1e-7f);
    EXPECT_NEAR(m.texcoords0[1].y, 0.2f, 1e-7f);  // 51 / 255
    ASSERT_EQ(m.texcoords1.size(), 3u);
    EXPECT_EQ(m.texcoords1[0], glm::vec2(0.0f, 1.0f));
    EXPECT_NEAR(m.texcoords1[1].x, 32768.0f / 65535.0f, 1e-7f);
    EXPECT_NEAR(m.texcoords1[1].y, 0.2f, 1e-7f);  // 13107 / 65535
    EXPECT_NEAR(m.texcoords1[2].x, 1.0f / 65535.0f, 1e-9f);
    ASSERT_EQ(m.colors.size(), 3u);
    expectNear(m.colors[0], {1, 0, 0, 1});
    expectNear(m.colors[1], {0, 32768.0f / 65535.0f, 0, 1});
    expectNear(m.colors[2], {0, 0, 0.2f, 1});
}

TEST(GltfAttributes, QuantizedTypesNeedKhrMeshQuantization) {
    TempDir dir;
    Triangle t;
    t.add("TEXCOORD_0", attribute<int16_t>(t.g, {0, 0, 2, 0, 0, -3}, I16, "VEC2", 2, false));
    const std::string error = loadError(t.g.writeGltf(dir / "undeclared.gltf"));
    EXPECT_NE(error.find("mesh 'tri' TEXCOORD_0"), std::string::npos) << error;
    EXPECT_NE(error.find("must be FLOAT, normalized UNSIGNED_BYTE or normalized UNSIGNED_SHORT "
                         "VEC2, not SHORT"),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("KHR_mesh_quantization"), std::string::npos) << error;

    t.useQuantization();
    const Loaded loaded = load(t.g.writeGltf(dir / "declared.gltf"));
    EXPECT_EQ(loaded.warnings, "");  // a supported extension
    const scene::Mesh& m = loaded.scene.meshes.at(0);
    ASSERT_EQ(m.texcoords0.size(), 3u);
    EXPECT_EQ(m.texcoords0[1], glm::vec2(2, 0));  // not normalized: the integer's value
    EXPECT_EQ(m.texcoords0[2], glm::vec2(0, -3));
}

TEST(GltfAttributes, QuantizedSignedTypesAreNormalizedAsGltfSays) {
    TempDir dir;
    GltfBuilder g;
    // Integer positions (a dequantizing node scale of 1/100), byte normals,
    // short tangents and signed-byte texture coordinates.
    const int positions =
        attribute<uint16_t>(g, {0, 0, 0, 100, 0, 0, 0, 100, 0}, U16, "VEC3", 3, false);
    const int normals =
        attribute<int8_t>(g, {0, 0, 127, 0, 0, 127, 0, 0, 127}, I8, "VEC3", 3, true);
    const int mesh = g.mesh(positions, -1, normals);
    g.node({{"mesh", mesh}, {"name", "quantized"}, {"scale", {0.01, 0.01, 0.01}}});
    g.camera();
    auto add = [&](const char* name, int accessor) {
        g.doc["meshes"][mesh]["primitives"][0]["attributes"][name] = accessor;
    };
    add("TANGENT",
        attribute<int16_t>(g, {32767, 0, 0, 32767, 32767, 0, 0, -32768, 32767, 0, 0, -32767}, I16,
                           "VEC4", 4, true));
    add("TEXCOORD_0", attribute<int8_t>(g, {-128, -127, 127, 0, 64, -64}, I8, "VEC2", 2, true));
    g.doc["extensionsUsed"] = Json::array({"KHR_mesh_quantization"});
    g.doc["extensionsRequired"] = Json::array({"KHR_mesh_quantization"});
    const scene::Mesh m = firstMesh(g.writeGltf(dir / "signed.gltf"));
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_NEAR(m.positions[1].x, 1.0f, 1e-6f);
    EXPECT_NEAR(m.positions[2].y, 1.0f, 1e-6f);
    ASSERT_EQ(m.normals.size(), 3u);
    EXPECT_NEAR(m.normals[0].z, 1.0f, 1e-6f);
    ASSERT_EQ(m.tangents.size(), 3u);
    // -32768 / 32767 is below -1: clamped to -1, the bitangent sign.
    expectNear(m.tangents[0], {1, 0, 0, 1});
    expectNear(m.tangents[1], {1, 0, 0, -1});
    expectNear(m.tangents[2], {1, 0, 0, -1});
    ASSERT_EQ(m.texcoords0.size(), 3u);
    EXPECT_EQ(m.texcoords0[0], glm::vec2(-1.0f, -1.0f));  // -128 and -127 both map to -1
    EXPECT_EQ(m.texcoords0[1], glm::vec2(1.0f, 0.0f));
    EXPECT_NEAR(m.texcoords0[2].x, 64.0f / 127.0f, 1e-7f);
    EXPECT_NEAR(m.texcoords0[2].y, -64.0f / 127.0f, 1e-7f);
}

// The bitangent a renderer rebuilds, w (N x T), must be the bitangent the
// file's tangent frame had, carried by the transform: under a mirror that
// takes w changing sign (glTF 2.0, 3.7.2.1).
TEST(GltfAttributes, TangentsFollowTheTransformAndFlipTheirSignUnderAMirror) {
    const glm::vec3 fileTangent(1, 0, 0), fileNormal(0, 0, 1);
    const glm::vec3 fileBitangent = glm::cross(fileNormal, fileTangent);  // w = +1: (0, 1, 0)
    struct Case {
        const char* name;
        Json node;
        glm::mat3 linear;
        float w;
    };
    const float c = std::cos(0.5f), s = std::sin(0.5f);
    const std::vector<Case> cases = {
        {"rotation",
         {{"rotation", {0, 0, std::sin(0.25), std::cos(0.25)}}},
         glm::mat3(glm::vec3(c, s, 0), glm::vec3(-s, c, 0), glm::vec3(0, 0, 1)),
         1.0f},
        {"mirror",
         {{"scale", {-2, 1, 1}}},
         glm::mat3(glm::vec3(-2, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)),
         -1.0f},
    };
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        TempDir dir;
        Triangle t(k.node);
        t.add("TANGENT",
              attribute<float>(t.g, {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, F32, "VEC4", 4, false));
        const scene::Mesh m = firstMesh(t.g.writeGltf(dir / "frame.gltf"));
        ASSERT_EQ(m.tangents.size(), 3u);
        const glm::vec3 tangent(m.tangents[0]);
        EXPECT_NEAR(glm::length(tangent), 1.0f, 1e-6f);
        const glm::vec3 expected = glm::normalize(k.linear * fileTangent);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(tangent[i], expected[i], 1e-6f);
        EXPECT_EQ(m.tangents[0].w, k.w);
        const glm::vec3 rebuilt = m.tangents[0].w * glm::cross(m.normals[0], tangent);
        const glm::vec3 carried = glm::normalize(k.linear * fileBitangent);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(rebuilt[i], carried[i], 1e-6f);
    }
}

TEST(GltfAttributes, StripsAndFansCarryTheAttributes) {
    TempDir dir;
    GltfBuilder g;
    const int positions = g.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
    const int mesh = g.mesh(positions, -1, -1, -1, 5);  // TRIANGLE_STRIP
    g.doc["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_0"] =
        attribute<float>(g, {0, 1, 1, 1, 0, 0, 1, 0}, F32, "VEC2", 2, false);
    g.doc["meshes"][mesh]["primitives"][0]["attributes"]["COLOR_0"] = attribute<uint8_t>(
        g, {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255}, U8, "VEC3", 3, true);
    g.node({{"mesh", mesh}});
    g.camera();
    const scene::Mesh m = firstMesh(g.writeGltf(dir / "strip.gltf"));
    ASSERT_EQ(m.triangles.size(), 2u);
    ASSERT_EQ(m.texcoords0.size(), 4u);
    ASSERT_EQ(m.colors.size(), 4u);
    // Triangle 1 of the strip is (v1, v3, v2); its corners keep their own attributes.
    EXPECT_EQ(m.triangles[1], glm::uvec3(1, 3, 2));
    EXPECT_EQ(m.texcoords0[m.triangles[1].y], glm::vec2(1, 0));
    EXPECT_EQ(m.colors[m.triangles[1].y], glm::vec4(1, 1, 1, 1));
    EXPECT_EQ(m.colors[m.triangles[1].z], glm::vec4(0, 0, 1, 1));
}

TEST(GltfAttributes, ColoursOutsideTheUnitRangeAreClampedWithAWarning) {
    TempDir dir;
    Triangle t;
    t.add("COLOR_0", attribute<float>(t.g, {2, 0.5f, -1, 1, 1, 1, 0, 0, 0}, F32, "VEC3", 3, false));
    const Loaded loaded = load(t.g.writeGltf(dir / "bright.gltf"));
    EXPECT_NE(loaded.warnings.find("vertex colours outside [0, 1] are clamped (1 mesh"),
              std::string::npos)
        << loaded.warnings;
    EXPECT_EQ(loaded.scene.meshes.at(0).colors[0], glm::vec4(1, 0.5f, 0, 1));
}

TEST(GltfAttributes, OtherSetsAreIgnoredWithAWarning) {
    TempDir dir;
    Triangle t;
    t.add("TEXCOORD_2", attribute<float>(t.g, {0, 0, 1, 0, 0, 1}, F32, "VEC2", 2, false));
    t.add("COLOR_1", attribute<float>(t.g, {1, 1, 1, 1, 1, 1, 1, 1, 1}, F32, "VEC3", 3, false));
    const Loaded loaded = load(t.g.writeGltf(dir / "sets.gltf"));
    EXPECT_NE(loaded.warnings.find("TEXCOORD_1 are ignored"), std::string::npos);
    EXPECT_NE(loaded.warnings.find("other than COLOR_0 are ignored"), std::string::npos);
    EXPECT_TRUE(loaded.scene.meshes.at(0).texcoords0.empty());
    EXPECT_TRUE(loaded.scene.meshes.at(0).colors.empty());
}

// ---- bad attributes: one line naming the file, the mesh and the attribute ----

void expectAttributeError(const std::string& error, const std::string& attribute,
                          const std::string& problem) {
    EXPECT_NE(error.find("mesh 'tri' " + attribute), std::string::npos) << error;
    EXPECT_NE(error.find(problem), std::string::npos) << error;
}

TEST(GltfBadInput, AttributeCountDiffersFromPositions) {
    TempDir dir;
    for (const char* name : {"TEXCOORD_0", "TEXCOORD_1", "COLOR_0"}) {
        Triangle t;
        t.add(name,
              attribute<float>(t.g, {0, 0, 1, 0, 1, 1, 0, 1}, F32, name[0] == 'C' ? "VEC4" : "VEC2",
                               name[0] == 'C' ? 4 : 2, false));
        expectAttributeError(
            loadError(t.g.writeGltf(dir / "count.gltf")), name,
            name[0] == 'C' ? "2 elements for 3 positions" : "4 elements for 3 positions");
    }
    Triangle t;
    t.add("TANGENT", attribute<float>(t.g, {1, 0, 0, 1, 1, 0, 0, 1}, F32, "VEC4", 4, false));
    expectAttributeError(loadError(t.g.writeGltf(dir / "tangents.gltf")), "TANGENT",
                         "2 elements for 3 positions");
}

TEST(GltfBadInput, NonFiniteAttributeValues) {
    TempDir dir;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    Triangle uv;
    uv.add("TEXCOORD_0", attribute<float>(uv.g, {0, 0, nan, 0, 0, 1}, F32, "VEC2", 2, false));
    expectAttributeError(loadError(uv.g.writeGltf(dir / "uv.gltf")), "TEXCOORD_0",
                         "element 1 is not finite");
    Triangle tangent;
    tangent.add("TANGENT", attribute<float>(tangent.g, {1, 0, 0, 1, 1, 0, 0, inf, 1, 0, 0, 1}, F32,
                                            "VEC4", 4, false));
    expectAttributeError(loadError(tangent.g.writeGltf(dir / "tangent.gltf")), "TANGENT",
                         "element 1 is not finite");
}

TEST(GltfBadInput, AttributeOfAnEncodingGltfDoesNotAllow) {
    TempDir dir;
    Triangle colour;  // integer colours must be normalized
    colour.add("COLOR_0", attribute<uint8_t>(colour.g, {255, 0, 0, 255, 0, 0, 255, 0, 0}, U8,
                                             "VEC3", 3, false));
    expectAttributeError(loadError(colour.g.writeGltf(dir / "colour.gltf")), "COLOR_0",
                         "must be FLOAT, normalized UNSIGNED_BYTE or normalized UNSIGNED_SHORT "
                         "VEC3 or VEC4, not UNSIGNED_BYTE VEC3");
    Triangle tangent;  // tangents are VEC4, quantized or not
    tangent.useQuantization();
    tangent.add("TANGENT",
                attribute<float>(tangent.g, {1, 0, 0, 1, 0, 0, 1, 0, 0}, F32, "VEC3", 3, false));
    expectAttributeError(loadError(tangent.g.writeGltf(dir / "tangent.gltf")), "TANGENT",
                         "not FLOAT VEC3");
}

}  // namespace
