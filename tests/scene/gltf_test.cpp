// The glTF importer: the bundled assets, transforms, index types, containers,
// cameras, the material mapping table, warnings, and one test per kind of bad
// input. Each test writes the small glTF files it needs into its own folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <sstream>
#include <string>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#include <nlohmann/json.hpp>
#pragma GCC diagnostic pop

#include "app/render_options.h"
#include "image/image.h"
#include "input_error.h"
#include "scene/camera.h"
#include "scene/gltf_loader.h"
#include "scene/load.h"
#include "support/gltf_builder.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using namespace vkpath;

using test::F32;
using test::U16;
using test::U32;
using test::U8;

// A folder of its own for each test, removed afterwards.
using test::TempDir;

using test::base64;
using test::GltfBuilder;
using test::load;
using test::Loaded;
using test::loadError;
using test::writeBytes;
using test::writeText;

std::vector<uint8_t> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

size_t countLinesContaining(const std::string& text, const std::string& needle) {
    size_t n = 0;
    for (const std::string& line : lines(text)) n += line.find(needle) != std::string::npos;
    return n;
}

glm::vec3 faceNormal(const scene::Mesh& mesh, size_t t) {
    const glm::uvec3 tri = mesh.triangles[t];
    return glm::normalize(glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                     mesh.positions[tri.z] - mesh.positions[tri.x]));
}

void expectVec3Near(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

// ---------------------------------------------------------------------------
// Bundled assets
// ---------------------------------------------------------------------------

TEST(GltfAssets, CornellBoxLoads) {
    const Loaded loaded = load(test::sourcePath("assets/cornell_box.gltf"));
    const scene::Scene& s = loaded.scene;
    EXPECT_EQ(loaded.warnings, "");
    EXPECT_EQ(s.meshes.size(), 4u);  // white walls, red wall, green wall, lamp
    EXPECT_EQ(s.triangleCount(), 12u);
    EXPECT_EQ(s.spheres.size(), 2u);
    ASSERT_EQ(s.materials.size(), 6u);
    const scene::FeatureSummary f = s.features();
    EXPECT_TRUE(f.triangles && f.spheres && f.diffuse && f.conductor && f.glass &&
                f.emissiveSurfaces);
    EXPECT_FALSE(f.mirror || f.roughGlass || f.metallicRoughness);
    EXPECT_FALSE(f.pointLights || f.spotLights || f.directionalLights || f.environment);

    // Red on the camera's left (-X), green on its right.
    for (const scene::Mesh& m : s.meshes) {
        const glm::vec3 albedo = s.materials[m.material].reflectance;
        if (m.name == "red_wall") {
            EXPECT_GT(albedo.x, 3 * albedo.y);
            EXPECT_LT(m.positions[0].x, 0.0f);
        }
        if (m.name == "green_wall") {
            EXPECT_GT(albedo.y, 2 * albedo.x);
            EXPECT_GT(m.positions[0].x, 0.0f);
        }
        if (m.name == "lamp") {
            expectVec3Near(s.materials[m.material].emission, {17, 12, 4}, 1e-4f);
            EXPECT_LT(faceNormal(m, 0).y, -0.99f);  // faces down into the box
        }
    }
    for (const scene::Sphere& sphere : s.spheres) {
        EXPECT_FLOAT_EQ(sphere.radius, 0.1f);
        EXPECT_FLOAT_EQ(sphere.center.y, 0.1f);  // resting on the floor
    }
    // glTF's smooth metal: the conductor with Schlick's F0 = base colour.
    const scene::Material& mirror = s.materials[s.spheres[0].material];
    EXPECT_EQ(mirror.kind, scene::MaterialKind::Conductor);
    EXPECT_EQ(mirror.roughness, 0.0f);
    const scene::Material& glass = s.materials[s.spheres[1].material];
    EXPECT_EQ(glass.kind, scene::MaterialKind::Dielectric);
    EXPECT_FLOAT_EQ(glass.ior, 1.5f);

    EXPECT_EQ(s.camera.name, "camera");
    expectVec3Near(s.camera.position, {0, 0.273f, 0.8f}, 1e-6f);
    expectVec3Near(glm::normalize(s.camera.target - s.camera.position), {0, 0, -1}, 1e-6f);
    EXPECT_NEAR(s.camera.xfovDegrees, 39.3077f, 1e-3f);  // square: horizontal = vertical
    EXPECT_FLOAT_EQ(s.camera.aspect, 1.0f);
}

TEST(GltfAssets, DiffuseCornellBoxHasOnlyDiffuseMaterials) {
    const Loaded loaded = load(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    EXPECT_EQ(loaded.warnings, "");
    const scene::FeatureSummary f = loaded.scene.features();
    EXPECT_TRUE(f.triangles && f.spheres && f.diffuse && f.emissiveSurfaces);
    EXPECT_FALSE(f.mirror || f.glass);
    EXPECT_EQ(loaded.scene.triangleCount(), 12u);
    EXPECT_EQ(loaded.scene.spheres.size(), 2u);
}

// The environment-lit scene: three spheres on a ground, and the bundled sky
// named by VKPATH_environment.
TEST(GltfAssets, SkySpheresIsLitByTheBundledSky) {
    const Loaded loaded = load(test::sourcePath("assets/sky_spheres.gltf"));
    EXPECT_EQ(loaded.warnings, "");
    const scene::Scene& s = loaded.scene;
    EXPECT_EQ(s.triangleCount(), 2u);
    ASSERT_EQ(s.spheres.size(), 3u);
    const scene::FeatureSummary f = s.features();
    EXPECT_TRUE(f.diffuse && f.conductor && f.glass && f.environment);
    EXPECT_FALSE(f.emissiveSurfaces);
    ASSERT_TRUE(s.environment && s.environment->map);
    EXPECT_EQ(s.environment->map->width, 2048u);
    EXPECT_EQ(s.environment->map->height, 1024u);
    EXPECT_FLOAT_EQ(s.environment->strength, 1.0f);
    // The camera looks at the middle sphere's centre.
    expectVec3Near(glm::normalize(s.camera.target - s.camera.position),
                   glm::normalize(glm::vec3(0, 0.5f, 0) - s.camera.position), 1e-5f);
}

TEST(GltfAssets, LoadSceneDispatchesGltf) {
    testing::internal::CaptureStderr();
    const scene::Scene s = scene::loadScene(test::sourcePath("assets/cornell_box.gltf"));
    testing::internal::GetCapturedStderr();
    EXPECT_EQ(s.triangleCount(), 12u);
}

// tools/make-assets is deterministic: running it again gives the committed bytes.
TEST(GltfAssets, GeneratorReproducesCommittedAssets) {
    if (std::system("command -v python3 >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "python3 is not installed";
    TempDir dir;
    const std::string command = "python3 '" + test::sourcePath("tools/make-assets").string() +
                                "' --out '" + dir.path().string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    for (const char* name : {"cornell_box.gltf", "cornell_box_diffuse.gltf", "sky.hdr",
                             "sky_spheres.gltf", "normal_maps.gltf", "material_extensions.gltf"}) {
        SCOPED_TRACE(name);
        const auto generated = readBytes(dir / name);
        const auto committed = readBytes(test::sourcePath(std::string("assets/") + name));
        ASSERT_FALSE(committed.empty());
        EXPECT_TRUE(generated == committed)
            << "assets/" << name << " differs from what tools/make-assets writes";
    }
}

// ---------------------------------------------------------------------------
// Transforms
// ---------------------------------------------------------------------------

TEST(GltfTransforms, TrsEqualsMatrix) {
    const glm::dvec3 t(1.0, -2.0, 0.5), s(2.0, 0.5, 1.5);
    const glm::dquat q = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1.0, 2.0, 3.0)));
    const glm::dmat4 m =
        glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(q) * glm::scale(glm::dmat4(1.0), s);
    std::vector<double> matrix(16);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) matrix[size_t(4 * c + r)] = m[c][r];

    TempDir dir;
    GltfBuilder trs, mat;
    trs.node({{"mesh", trs.triangle()},
              {"translation", {t.x, t.y, t.z}},
              {"rotation", {q.x, q.y, q.z, q.w}},
              {"scale", {s.x, s.y, s.z}}});
    mat.node({{"mesh", mat.triangle()}, {"matrix", matrix}});
    const scene::Scene a = load(trs.writeGltf(dir / "trs.gltf")).scene;
    const scene::Scene b = load(mat.writeGltf(dir / "matrix.gltf")).scene;
    ASSERT_EQ(a.meshes.size(), 1u);
    ASSERT_EQ(b.meshes.size(), 1u);
    const std::vector<glm::dvec3> local = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (size_t i = 0; i < 3; ++i) {
        expectVec3Near(a.meshes[0].positions[i], b.meshes[0].positions[i], 1e-5f);
        expectVec3Near(a.meshes[0].normals[i], b.meshes[0].normals[i], 1e-5f);
        expectVec3Near(a.meshes[0].positions[i], glm::vec3(m * glm::dvec4(local[i], 1.0)), 1e-5f);
    }
    EXPECT_EQ(a.meshes[0].triangles, b.meshes[0].triangles);
}

TEST(GltfTransforms, HierarchyComposesParentThenChild) {
    TempDir dir;
    GltfBuilder g;
    const int child = g.node({{"mesh", g.triangle()}, {"translation", {1, 0, 0}}}, false);
    // Parent: rotate 90 degrees about +Y (x -> -z), then move up 5.
    const double h = std::sqrt(0.5);
    g.node({{"children", {child}}, {"translation", {0, 5, 0}}, {"rotation", {0, h, 0, h}}});
    const scene::Scene s = load(g.writeGltf(dir / "h.gltf")).scene;
    ASSERT_EQ(s.meshes.size(), 1u);
    expectVec3Near(s.meshes[0].positions[0], {0, 5, -1},
                   1e-6f);  // child origin (1, 0, 0) -> (0, 0, -1) + up
    expectVec3Near(s.meshes[0].positions[1], {0, 5, -2}, 1e-6f);
    expectVec3Near(s.meshes[0].normals[0], {1, 0, 0}, 1e-6f);  // +Z rotated to +X
}

TEST(GltfTransforms, NegativeScaleFlipsWinding) {
    TempDir dir;
    GltfBuilder plain, mirrored;
    plain.node({{"mesh", plain.triangle()}});
    mirrored.node({{"mesh", mirrored.triangle()}, {"scale", {1, 1, -1}}});  // mirror through z = 0
    const scene::Scene a = load(plain.writeGltf(dir / "plain.gltf")).scene;
    const scene::Scene b = load(mirrored.writeGltf(dir / "mirrored.gltf")).scene;
    expectVec3Near(faceNormal(a.meshes[0], 0), {0, 0, 1}, 1e-6f);
    // Mirrored: the shading normal becomes -Z, and so must the winding's normal.
    expectVec3Near(b.meshes[0].normals[0], {0, 0, -1}, 1e-6f);
    expectVec3Near(faceNormal(b.meshes[0], 0), {0, 0, -1}, 1e-6f);
    EXPECT_NE(a.meshes[0].triangles[0], b.meshes[0].triangles[0]);
}

TEST(GltfTransforms, NormalsStayPerpendicularUnderNonUniformScale) {
    // A slanted triangle whose vertex normals equal its face normal.
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 1}, {0, 1, 1}};
    const glm::vec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
    TempDir dir;
    GltfBuilder g;
    const int mesh = g.mesh(g.vec3s(p), -1, g.vec3s({n, n, n}));
    const double h = std::sqrt(0.5);
    g.node({{"mesh", mesh}, {"scale", {3, 0.5, 1}}, {"rotation", {h, 0, 0, h}}});
    const scene::Scene s = load(g.writeGltf(dir / "n.gltf")).scene;
    const glm::vec3 face = faceNormal(s.meshes[0], 0);
    for (const glm::vec3& normal : s.meshes[0].normals) {
        EXPECT_NEAR(glm::length(normal), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(normal, face), 1.0f,
                    1e-6f);  // still the face normal: perpendicular to the surface
    }
    // Transforming the normal like a direction would have tilted it: the test can fail.
    const glm::mat3 linear = glm::mat3_cast(glm::quat(float(h), float(h), 0.0f, 0.0f)) *
                             glm::mat3(glm::scale(glm::mat4(1.0f), glm::vec3(3.0f, 0.5f, 1.0f)));
    EXPECT_LT(glm::dot(glm::normalize(linear * n), face), 0.99f);
}

// ---------------------------------------------------------------------------
// Indices, layouts, containers
// ---------------------------------------------------------------------------

class GltfIndexTypes : public testing::TestWithParam<int> {};

TEST_P(GltfIndexTypes, IndexedQuad) {
    TempDir dir;
    GltfBuilder g;
    const int positions = g.vec3s({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    g.node({{"mesh", g.mesh(positions, g.indices({0, 1, 2, 0, 2, 3}, GetParam()))}});
    const scene::Scene s = load(g.writeGltf(dir / "quad.gltf")).scene;
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}));
    EXPECT_TRUE(s.meshes[0].normals.empty());  // no NORMAL: face normals
}

INSTANTIATE_TEST_SUITE_P(Components, GltfIndexTypes, testing::Values(U8, U16, U32),
                         [](const testing::TestParamInfo<int>& p) {
                             return p.param == U8    ? std::string("U8")
                                    : p.param == U16 ? std::string("U16")
                                                     : std::string("U32");
                         });

TEST(GltfLayouts, NonIndexedTriangles) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh",
             g.mesh(g.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}}))}});
    const scene::Scene s = load(g.writeGltf(dir / "soup.gltf")).scene;
    EXPECT_EQ(s.meshes[0].triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {3, 4, 5}}));
}

TEST(GltfLayouts, InterleavedAttributesWithStride) {
    TempDir dir;
    GltfBuilder g;
    // position, normal, position, normal, ... with a 24-byte stride.
    const std::vector<glm::vec3> interleaved = {{0, 0, 0}, {0, 0, 1}, {2, 0, 0},
                                                {0, 0, 1}, {0, 2, 0}, {0, 0, 1}};
    const int view = g.view(interleaved.data(), interleaved.size() * sizeof(glm::vec3), 24);
    const int positions = g.accessor(view, F32, "VEC3", 3);
    const int normals = g.accessor(view, F32, "VEC3", 3, 12);
    g.node({{"mesh", g.mesh(positions, -1, normals)}});
    const scene::Scene s = load(g.writeGltf(dir / "interleaved.gltf")).scene;
    expectVec3Near(s.meshes[0].positions[1], {2, 0, 0}, 0);
    expectVec3Near(s.meshes[0].positions[2], {0, 2, 0}, 0);
    expectVec3Near(s.meshes[0].normals[2], {0, 0, 1}, 0);
}

TEST(GltfLayouts, SparseAccessorSubstitutesValues) {
    TempDir dir;
    GltfBuilder g;
    const int positions = g.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const std::vector<uint16_t> sparseIndices = {2};
    const std::vector<glm::vec3> sparseValues = {{0, 7, 0}};
    const int indexView = g.view(sparseIndices.data(), 2);
    const int valueView = g.view(sparseValues.data(), 12);
    g.doc["accessors"][positions]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", indexView}, {"componentType", U16}}},
        {"values", {{"bufferView", valueView}}}};
    g.node({{"mesh", g.mesh(positions)}});
    const scene::Scene s = load(g.writeGltf(dir / "sparse.gltf")).scene;
    expectVec3Near(s.meshes[0].positions[2], {0, 7, 0}, 0);
    expectVec3Near(s.meshes[0].positions[1], {1, 0, 0}, 0);
}

TEST(GltfLayouts, ExternalBufferFile) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    const Loaded loaded = load(g.writeGltf(dir / "external.gltf", GltfBuilder::Buffer::External));
    EXPECT_EQ(loaded.scene.triangleCount(), 1u);
}

// The files a scene refers to are part of its identity (app::renderIdentity):
// a checkpoint or a merge part of the scene before its .bin changed is
// another scene's.
TEST(GltfLayouts, ReferencedFilesAreListedAndHashed) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    g.camera();
    const fs::path path = g.writeGltf(dir / "external.gltf", GltfBuilder::Buffer::External);
    const scene::Scene scene = load(path).scene;
    ASSERT_EQ(scene.referencedFiles.size(), 1u);
    EXPECT_TRUE(fs::equivalent(scene.referencedFiles[0], dir / "external.bin"));
    app::RenderOptions options;
    options.scene = path.string();
    const std::string before = app::renderIdentity(options, scene).sceneHash;
    std::vector<uint8_t> bin(fs::file_size(dir / "external.bin"));
    std::ifstream(dir / "external.bin", std::ios::binary)
        .read(reinterpret_cast<char*>(bin.data()), std::streamsize(bin.size()));
    bin[0] ^= 1;  // one bit of a vertex position
    std::ofstream(dir / "external.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
    EXPECT_NE(app::renderIdentity(options, load(path).scene).sceneHash, before);
}

TEST(GltfLayouts, GlbRoundTripEqualsGltf) {
    TempDir dir;
    GltfBuilder g;
    const int red =
        g.material({{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.1, 0.1, 1}}}}});
    g.node({{"mesh", g.triangle(red)}, {"translation", {0, 1, 0}}});
    g.node({{"extensions", {{"VKPATH_sphere", {{"radius", 0.5}, {"material", red}}}}}});
    const scene::Scene a = load(g.writeGltf(dir / "scene.gltf")).scene;
    const scene::Scene b = load(g.writeGlb(dir / "scene.glb")).scene;
    ASSERT_EQ(a.meshes.size(), 1u);
    ASSERT_EQ(b.meshes.size(), 1u);
    EXPECT_EQ(a.meshes[0].positions, b.meshes[0].positions);
    EXPECT_EQ(a.meshes[0].normals, b.meshes[0].normals);
    EXPECT_EQ(a.meshes[0].triangles, b.meshes[0].triangles);
    ASSERT_EQ(b.spheres.size(), 1u);
    EXPECT_EQ(b.spheres[0].radius, 0.5f);
    ASSERT_EQ(b.materials.size(), 1u);
    EXPECT_EQ(a.materials[0].reflectance, b.materials[0].reflectance);
    // The magic decides, not the extension.
    fs::copy_file(dir / "scene.glb", dir / "binary.gltf");
    EXPECT_EQ(load(dir / "binary.gltf").scene.triangleCount(), 1u);
}

// ---------------------------------------------------------------------------
// Cameras
// ---------------------------------------------------------------------------

Json perspective(const std::string& name, double yfov, double aspect = 0.0) {
    Json p = {{"yfov", yfov}, {"znear", 0.01}};
    if (aspect > 0) p["aspectRatio"] = aspect;
    return {{"name", name}, {"type", "perspective"}, {"perspective", p}};
}

TEST(GltfCameras, FirstCameraInNodeOrder) {
    TempDir dir;
    GltfBuilder g;
    g.doc["cameras"] = {perspective("late", 0.5), perspective("early", 0.6)};
    // Node 0 (the "late" camera) comes first in the file, but the scene
    // lists it after a root whose subtree holds the "early" camera.
    const int lateNode = g.node({{"camera", 0}, {"name", "late-node"}}, false);
    const int earlyNode = g.node({{"camera", 1}, {"translation", {0, 0, 3}}}, false);
    g.node({{"mesh", g.triangle()}, {"children", {earlyNode}}});
    g.doc["scenes"][0]["nodes"].push_back(lateNode);
    const scene::Scene s = load(g.writeGltf(dir / "cameras.gltf")).scene;
    EXPECT_EQ(s.camera.name, "early");
    expectVec3Near(s.camera.position, {0, 0, 3}, 0);
}

TEST(GltfCameras, SelectByCameraOrNodeName) {
    TempDir dir;
    GltfBuilder g;
    g.doc["cameras"] = {perspective("front", 0.5), perspective("side", 0.5)};
    g.node({{"mesh", g.triangle()}});
    g.node({{"camera", 0}, {"name", "front-node"}, {"translation", {0, 0, 5}}});
    const double h = std::sqrt(0.5);  // 90 degrees about +Y: -Z turns into -X
    g.node({{"camera", 1},
            {"name", "side-node"},
            {"translation", {5, 0, 0}},
            {"rotation", {0, h, 0, h}}});
    const fs::path path = g.writeGltf(dir / "cameras.gltf");

    const scene::Scene side = load(path, {.cameraName = "side"}).scene;
    EXPECT_EQ(side.camera.name, "side");
    expectVec3Near(side.camera.position, {5, 0, 0}, 1e-6f);
    expectVec3Near(side.camera.target - side.camera.position, {-1, 0, 0}, 1e-6f);
    expectVec3Near(side.camera.up, {0, 1, 0}, 1e-6f);

    EXPECT_EQ(load(path, {.cameraName = "front-node"}).scene.camera.name, "front");
    const std::string error = loadError(path, {.cameraName = "top"});
    EXPECT_CONTAINS(error, "no camera named 'top'");
    EXPECT_CONTAINS(error, "'front', 'side'");
}

TEST(GltfCameras, VerticalFovBecomesHorizontal) {
    TempDir dir;
    GltfBuilder g;
    g.doc["cameras"] = {perspective("wide", 0.5, 2.0), perspective("unknown-aspect", 0.5)};
    g.node({{"mesh", g.triangle()}});
    g.node({{"camera", 0}, {"translation", {0, 0, 5}}});
    g.node({{"camera", 1}, {"translation", {0, 0, 5}}});
    const fs::path path = g.writeGltf(dir / "fov.gltf");

    const scene::Camera wide = load(path, {.cameraName = "wide"}).scene.camera;
    EXPECT_FLOAT_EQ(wide.aspect, 2.0f);
    EXPECT_NEAR(wide.xfovDegrees, glm::degrees(2.0 * std::atan(2.0 * std::tan(0.25))), 1e-4);
    // On a film of the camera's aspect, the vertical fov is exactly yfov.
    const auto gpu = scene::makeGpuCamera(wide, 400, 200);
    EXPECT_NEAR(glm::length(gpu.up), std::tan(0.25), 1e-6);

    // No aspectRatio: taken as square, so yfov stays vertical on wide films.
    const scene::Camera square = load(path, {.cameraName = "unknown-aspect"}).scene.camera;
    EXPECT_FLOAT_EQ(square.aspect, 1.0f);
    EXPECT_NEAR(square.xfovDegrees, glm::degrees(0.5), 1e-4);
    EXPECT_NEAR(glm::length(scene::makeGpuCamera(square, 1600, 900).up), std::tan(0.25), 1e-6);
}

TEST(GltfCameras, DefaultCameraFramesTheScene) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}, {"translation", {10, 0, 0}}, {"scale", {4, 4, 4}}});
    g.node({{"extensions", {{"VKPATH_sphere", {{"radius", 1.0}}}}}, {"translation", {20, 0, 0}}});
    const Loaded loaded = load(g.writeGltf(dir / "nocamera.gltf"));
    EXPECT_EQ(countLinesContaining(loaded.warnings, "default camera"), 1u);
    const scene::Camera& c = loaded.scene.camera;
    EXPECT_EQ(c.name, "default");
    expectVec3Near(c.target, {15.5f, 1.5f, 0.0f}, 1e-5f);  // box [10, 21] x [-1, 4] x [-1, 1]
    // Every corner of the bounding box lies within half the fov of the view axis.
    const glm::vec3 forward = glm::normalize(c.target - c.position);
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner(i & 1 ? 21.0f : 10.0f, i & 2 ? 4.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
        const float angle =
            glm::degrees(std::acos(glm::dot(glm::normalize(corner - c.position), forward)));
        EXPECT_LT(angle, c.xfovDegrees / 2);
    }
}

// ---------------------------------------------------------------------------
// Materials: one small file per row of docs/SCENES.md's table
// ---------------------------------------------------------------------------

struct MaterialRow {
    const char* name;
    const char* material;  // glTF material JSON; "" for a primitive with no material
    scene::MaterialKind kind;
    glm::vec3 reflectance;
    glm::vec3 transmittance;
    float ior;
    glm::vec3 emission;
    const char* warning;  // a phrase of the one expected warning line; "" for none
    scene::AlphaMode alphaMode = scene::AlphaMode::Opaque;
    float alphaCutoff = 0.5f;
    float alpha = 1.0f;
    float roughness = -1.0f;  // checked where >= 0
    float metallic = -1.0f;   // checked where >= 0
};

void PrintTo(const MaterialRow& row, std::ostream* os) {
    *os << row.name;
}

class GltfMaterialTable : public testing::TestWithParam<MaterialRow> {};

TEST_P(GltfMaterialTable, MapsAsDocumented) {
    const MaterialRow& row = GetParam();
    TempDir dir;
    GltfBuilder g;
    int material = -1;
    if (*row.material) {
        g.doc["textures"] = {{{"source", 0}}};
        g.doc["images"] = {{{"uri", "texture.png"}}};
        writeText(dir / "texture.png", "not decoded");
        material = g.material(Json::parse(row.material));
    }
    g.node({{"mesh", g.triangle(material)}});
    g.camera();
    const Loaded loaded = load(g.writeGltf(dir / "material.gltf"));
    const scene::Material& m = loaded.scene.materials.at(loaded.scene.meshes.at(0).material);
    EXPECT_EQ(m.kind, row.kind);
    expectVec3Near(m.reflectance, row.reflectance, 1e-6f);
    expectVec3Near(m.transmittance, row.transmittance, 1e-6f);
    EXPECT_FLOAT_EQ(m.ior, row.ior);
    expectVec3Near(m.emission, row.emission, 1e-5f);
    EXPECT_EQ(m.alphaMode, row.alphaMode);
    EXPECT_FLOAT_EQ(m.alphaCutoff, row.alphaCutoff);
    EXPECT_FLOAT_EQ(m.alpha, row.alpha);
    if (row.roughness >= 0.0f) {
        EXPECT_FLOAT_EQ(m.roughness, row.roughness);
    }
    if (row.metallic >= 0.0f) {
        EXPECT_FLOAT_EQ(m.metallic, row.metallic);
    }
    if (*row.warning) {
        EXPECT_EQ(lines(loaded.warnings).size(), 1u) << loaded.warnings;
        EXPECT_CONTAINS(loaded.warnings, row.warning);
    } else {
        EXPECT_EQ(loaded.warnings, "");
    }
}

constexpr scene::MaterialKind DIFFUSE = scene::MaterialKind::Diffuse;
constexpr scene::MaterialKind CONDUCTOR = scene::MaterialKind::Conductor;
constexpr scene::MaterialKind LAYERED = scene::MaterialKind::MetallicRoughness;
constexpr scene::MaterialKind GLASS = scene::MaterialKind::Dielectric;
constexpr scene::MaterialKind ROUGH_GLASS = scene::MaterialKind::RoughDielectric;
constexpr scene::AlphaMode OPAQUE = scene::AlphaMode::Opaque;

INSTANTIATE_TEST_SUITE_P(
    Rows, GltfMaterialTable,
    testing::Values(
        MaterialRow{"Default", "", DIFFUSE, glm::vec3(0.8f), glm::vec3(1), 1.5f, glm::vec3(0), ""},
        MaterialRow{
            "NonMetalIsLayered",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0}})",
            LAYERED,
            {0.2f, 0.4f, 0.6f},
            glm::vec3(1),
            1.5f,
            glm::vec3(0),
            "",
            OPAQUE,
            0.5f,
            1.0f,
            1.0f,
            0.0f},
        MaterialRow{
            "NoSpecularLayerIsLambertian",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0},
                        "extensions": {"KHR_materials_specular": {"specularFactor": 0}}})",
            DIFFUSE,
            {0.2f, 0.4f, 0.6f},
            glm::vec3(1),
            1.5f,
            glm::vec3(0),
            ""},
        MaterialRow{
            "SmoothMetal",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1], "roughnessFactor": 0}})",
            CONDUCTOR,
            {0.9f, 0.8f, 0.7f},
            glm::vec3(1),
            1.5f,
            glm::vec3(0),
            "",
            OPAQUE,
            0.5f,
            1.0f,
            0.0f,
            1.0f},
        MaterialRow{
            "RoughMetal",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1], "roughnessFactor": 0.3}})",
            CONDUCTOR,
            {0.9f, 0.8f, 0.7f},
            glm::vec3(1),
            1.5f,
            glm::vec3(0),
            "",
            OPAQUE,
            0.5f,
            1.0f,
            0.3f,
            1.0f},
        MaterialRow{"DefaultFactorsAreAVeryRoughMetal",
                    R"({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}})",
                    CONDUCTOR, glm::vec3(0.5f), glm::vec3(1), 1.5f, glm::vec3(0), "", OPAQUE, 0.5f,
                    1.0f, 1.0f, 1.0f},
        MaterialRow{"PartlyMetallic",
                    R"({"pbrMetallicRoughness": {"metallicFactor": 0.7, "roughnessFactor": 0.2}})",
                    LAYERED, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), "", OPAQUE, 0.5f, 1.0f,
                    0.2f, 0.7f},
        MaterialRow{
            "Glass",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 1, 0.9, 1], "metallicFactor": 0,
                        "roughnessFactor": 0}, "extensions": {"KHR_materials_transmission":
                        {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.33},
                        "KHR_materials_volume": {"thicknessFactor": 1}}})",
            GLASS,
            glm::vec3(1),
            {0.9f, 1.0f, 0.9f},
            1.33f,
            glm::vec3(0),
            ""},
        MaterialRow{
            "GlassDefaultIor",
            R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}, "extensions":
                        {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                         "KHR_materials_volume": {}}})",
            GLASS, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), ""},
        MaterialRow{
            "ThinWalledGlass",
            R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}, "extensions":
                        {"KHR_materials_transmission": {"transmissionFactor": 1.0}}})",
            GLASS, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), ""},
        MaterialRow{
            "RoughGlass",
            R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.4}, "extensions":
                        {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                         "KHR_materials_volume": {"thicknessFactor": 1}}})",
            ROUGH_GLASS, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), "", OPAQUE, 0.5f, 1.0f,
            0.4f},
        MaterialRow{
            "MostlyTransmissive",
            R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}, "extensions":
                        {"KHR_materials_transmission": {"transmissionFactor": 0.7}, "KHR_materials_volume": {}}})",
            GLASS, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), "partial transmission"},
        MaterialRow{
            "SlightlyTransmissive",
            R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.6}, "extensions":
                        {"KHR_materials_transmission": {"transmissionFactor": 0.3}}})",
            LAYERED, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), "partial transmission"},
        MaterialRow{
            "GlossyPlastic",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 1], "metallicFactor": 0,
                        "roughnessFactor": 0.2}, "extensions": {"KHR_materials_ior": {"ior": 1.4}}})",
            LAYERED,
            {0.1f, 0.2f, 0.3f},
            glm::vec3(1),
            1.4f,
            glm::vec3(0),
            "",
            OPAQUE,
            0.5f,
            1.0f,
            0.2f,
            0.0f},
        MaterialRow{
            "EmissiveWithStrength",
            R"({"pbrMetallicRoughness": {"metallicFactor": 0}, "emissiveFactor": [1, 0.5, 0.25],
                        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}})",
            LAYERED,
            glm::vec3(1),
            glm::vec3(1),
            1.5f,
            {4.0f, 2.0f, 1.0f},
            ""},
        MaterialRow{
            "EmissiveFactorOnly",
            R"({"pbrMetallicRoughness": {"metallicFactor": 0}, "emissiveFactor": [0.5, 0.5, 0.5]})",
            LAYERED, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0.5f), ""},
        MaterialRow{
            "UndecodableTextureLeavesTheFactors",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.3, 0.3, 1], "metallicFactor": 0,
                        "baseColorTexture": {"index": 0}}})",
            LAYERED, glm::vec3(0.3f), glm::vec3(1), 1.5f, glm::vec3(0),
            "images that cannot be decoded"},
        MaterialRow{
            "AlphaBlend",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.3, 0.3, 0.5], "metallicFactor": 0},
                        "alphaMode": "BLEND"})",
            LAYERED, glm::vec3(0.3f), glm::vec3(1), 1.5f, glm::vec3(0), "", scene::AlphaMode::Blend,
            0.5f, 0.5f},
        MaterialRow{
            "AlphaMaskWithCutoff",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.3, 0.3, 0.25], "metallicFactor": 0},
                        "alphaMode": "MASK", "alphaCutoff": 0.2})",
            LAYERED, glm::vec3(0.3f), glm::vec3(1), 1.5f, glm::vec3(0), "", scene::AlphaMode::Mask,
            0.2f, 0.25f},
        MaterialRow{"AlphaMaskDefaultCutoff",
                    R"({"pbrMetallicRoughness": {"metallicFactor": 0}, "alphaMode": "MASK"})",
                    LAYERED, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), "",
                    scene::AlphaMode::Mask, 0.5f, 1.0f},
        MaterialRow{
            "AlphaOpaqueByDefault",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5], "metallicFactor": 0}})",
            LAYERED, glm::vec3(1), glm::vec3(1), 1.5f, glm::vec3(0), "", scene::AlphaMode::Opaque,
            0.5f, 0.5f},
        MaterialRow{
            "FactorsClamped",
            R"({"pbrMetallicRoughness": {"baseColorFactor": [1.5, 0.5, 0.5, 1], "metallicFactor": 0}})",
            LAYERED,
            {1.0f, 0.5f, 0.5f},
            glm::vec3(1),
            1.5f,
            glm::vec3(0),
            "clamped"}),
    [](const testing::TestParamInfo<MaterialRow>& p) { return std::string(p.param.name); });

// KHR_materials_volume's absorption: -ln(attenuationColor) / attenuationDistance
// per metre, clear by default (no distance, or a white colour), on glass only;
// a distance that is not > 0 is an error naming the material.
TEST(GltfVolume, AttenuationIsBeerLambertsCoefficient) {
    TempDir dir;
    auto glassWithVolume = [&](const std::string& volume, const char* file) {
        GltfBuilder g;
        const int material = g.material(Json::parse(
            R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}, "extensions":
                {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_volume": )" +
            volume + "}}"));
        g.node({{"mesh", g.triangle(material)}});
        g.camera();
        return g.writeGltf(dir / file);
    };
    const Loaded absorbing = load(glassWithVolume(
        R"({"attenuationDistance": 2, "attenuationColor": [0.5, 0.25, 1]})", "absorbing.gltf"));
    EXPECT_EQ(absorbing.warnings, "");
    expectVec3Near(absorbing.scene.materials.at(0).attenuation,
                   {float(std::log(2.0) / 2), float(std::log(4.0) / 2), 0.0f}, 1e-6f);
    const Loaded clear =
        load(glassWithVolume(R"({"attenuationColor": [0.5, 0.5, 0.5]})", "clear.gltf"));
    expectVec3Near(clear.scene.materials.at(0).attenuation, glm::vec3(0.0f), 0.0f);
    EXPECT_CONTAINS(loadError(glassWithVolume(R"({"attenuationDistance": 0})", "zero.gltf")),
                    "attenuationDistance 0 is not > 0");
}

// KHR_materials_volume_scatter: the share of the attenuation that scatters
// is the single-scattering albedo that Kulla and Conty's fit gives for
// multiscatterColor (0 and 1 map to themselves; 0.5 to 0.9117..., the fit
// evaluated here in double), and scatterAnisotropy is the phase function's
// g. Scattering without an attenuationDistance, or on a material without
// transmission, is warned about; g outside (-1, 1) is an error.
TEST(GltfVolume, VolumeScatterSplitsTheAttenuation) {
    TempDir dir;
    auto glass = [&](const std::string& extensions, const char* file) {
        GltfBuilder g;
        const int material = g.material(Json::parse(
            R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}, "extensions":
                {"KHR_materials_transmission": {"transmissionFactor": 1}, )" +
            extensions + "}}"));
        g.node({{"mesh", g.triangle(material)}});
        g.camera();
        return g.writeGltf(dir / file);
    };
    const Loaded milky = load(glass(
        R"("KHR_materials_volume": {"attenuationDistance": 0.5, "attenuationColor": [0.5, 0.5, 0.5]},
           "KHR_materials_volume_scatter": {"multiscatterColor": [0, 0.5, 1], "scatterAnisotropy": -0.3})",
        "milky.gltf"));
    EXPECT_EQ(milky.warnings, "");
    const scene::Material& m = milky.scene.materials.at(0);
    const double root =
        4.09712 + 4.20863 * 0.5 - std::sqrt(9.59217 + 41.6808 * 0.5 + 17.7126 * 0.25);
    expectVec3Near(m.scatteringAlbedo, {0.0f, float(1.0 - root * root), 1.0f}, 1e-6f);
    EXPECT_NEAR(m.scatteringAlbedo.y, 0.9117, 1e-4);
    EXPECT_FLOAT_EQ(m.scatterAnisotropy, -0.3f);
    expectVec3Near(m.attenuation, glm::vec3(float(2.0 * std::log(2.0))), 1e-6f);

    const Loaded unbounded = load(glass(
        R"("KHR_materials_volume": {}, "KHR_materials_volume_scatter": {"multiscatterColor": [1, 1, 1]})",
        "unbounded.gltf"));
    EXPECT_CONTAINS(unbounded.warnings, "scatters nothing");
    EXPECT_CONTAINS(loadError(glass(R"("KHR_materials_volume": {"attenuationDistance": 1},
                           "KHR_materials_volume_scatter": {"scatterAnisotropy": 1})",
                                    "forward.gltf")),
                    "scatterAnisotropy 1 is not in (-1, 1)");

    GltfBuilder opaque;
    const int material = opaque.material(Json::parse(
        R"({"extensions": {"KHR_materials_volume_scatter": {"multiscatterColor": [1, 1, 1]}}})"));
    opaque.node({{"mesh", opaque.triangle(material)}});
    opaque.camera();
    EXPECT_CONTAINS(load(opaque.writeGltf(dir / "opaque.gltf")).warnings,
                    "KHR_materials_volume_scatter without transmission is ignored");
}

// ---------------------------------------------------------------------------
// Lights and spheres
// ---------------------------------------------------------------------------

TEST(GltfLights, PunctualLightsTakeNodePositionAndMinusZ) {
    TempDir dir;
    GltfBuilder g;
    g.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    g.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 10}, {"range", 2.5}},
        {{"type", "spot"},
         {"intensity", 3},
         {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
        {{"type", "directional"}, {"color", {1, 1, 0.5}}, {"intensity", 2}}};
    const double h = std::sqrt(0.5);  // -90 degrees about +X: -Z turns into -Y
    g.node({{"mesh", g.triangle()}});
    g.node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    g.node({{"translation", {0, 4, 0}},
            {"rotation", {-h, 0, 0, h}},
            {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    g.node(
        {{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    g.camera();
    const Loaded loaded = load(g.writeGltf(dir / "lights.gltf"));
    EXPECT_EQ(loaded.warnings, "");
    const scene::Scene& s = loaded.scene;
    ASSERT_EQ(s.pointLights.size(), 1u);
    expectVec3Near(s.pointLights[0].position, {1, 2, 3}, 1e-6f);
    expectVec3Near(s.pointLights[0].intensity, {10, 5, 2.5f}, 1e-6f);  // candela taken as W/sr
    EXPECT_FLOAT_EQ(s.pointLights[0].range, 2.5f);  // not scaled by the node (the extension)
    ASSERT_EQ(s.spotLights.size(), 1u);
    expectVec3Near(s.spotLights[0].position, {0, 4, 0}, 1e-6f);
    expectVec3Near(s.spotLights[0].direction, {0, -1, 0}, 1e-6f);
    expectVec3Near(s.spotLights[0].intensity, glm::vec3(3), 1e-6f);
    EXPECT_FLOAT_EQ(s.spotLights[0].innerConeAngle, 0.2f);
    EXPECT_FLOAT_EQ(s.spotLights[0].outerConeAngle, 0.5f);
    EXPECT_EQ(s.spotLights[0].range, 0.0f);  // none given: infinite
    ASSERT_EQ(s.directionalLights.size(), 1u);
    expectVec3Near(s.directionalLights[0].direction, {0, -1, 0}, 1e-6f);
    expectVec3Near(s.directionalLights[0].irradiance, {2, 2, 1}, 1e-6f);  // lux taken as W/m^2
    const scene::FeatureSummary f = s.features();
    EXPECT_TRUE(f.pointLights && f.spotLights && f.directionalLights);
}

TEST(GltfLights, InvalidConeIsAnError) {
    TempDir dir;
    GltfBuilder g;
    g.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}}}};
    g.node({{"mesh", g.triangle()}});
    g.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "cone.gltf")), "cone angles");
}

TEST(GltfLights, ARangeNotAboveZeroOrOnADirectionalLightIsAnError) {
    for (const auto& [light, message] :
         {std::pair{Json{{"type", "point"}, {"range", -1}}, "range -1 is not > 0"},
          std::pair{Json{{"type", "directional"}, {"range", 3}}, "has no range"}}) {
        TempDir dir;
        GltfBuilder g;
        g.doc["extensions"]["KHR_lights_punctual"]["lights"] = {light};
        g.node({{"mesh", g.triangle()}});
        g.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
        EXPECT_CONTAINS(loadError(g.writeGltf(dir / "range.gltf")), message);
    }
}

TEST(GltfSpheres, CentreAndRadiusFollowTheNode) {
    TempDir dir;
    GltfBuilder g;
    const int glass = g.material(Json::parse(
        R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}, "extensions":
                        {"KHR_materials_transmission": {"transmissionFactor": 1.0}}})"));
    const int child =
        g.node({{"name", "ball"},
                {"translation", {1, 0, 0}},
                {"extensions", {{"VKPATH_sphere", {{"radius", 0.25}, {"material", glass}}}}}},
               false);
    g.node({{"children", {child}}, {"translation", {0, 1, 0}}, {"scale", {2, 2, 2}}});
    const Loaded loaded = load(g.writeGltf(dir / "sphere.gltf"));
    EXPECT_EQ(countLinesContaining(loaded.warnings, "default camera"), 1u);
    ASSERT_EQ(loaded.scene.spheres.size(), 1u);
    const scene::Sphere& s = loaded.scene.spheres[0];
    EXPECT_EQ(s.name, "ball");
    expectVec3Near(s.center, {2, 1, 0}, 1e-6f);
    EXPECT_FLOAT_EQ(s.radius, 0.5f);
    EXPECT_EQ(loaded.scene.materials[s.material].kind, scene::MaterialKind::Dielectric);
    EXPECT_TRUE(loaded.scene.features().spheres);
    EXPECT_FALSE(loaded.scene.features().triangles);
}

// Alpha is tested on triangles only: a sphere whose material has an
// alphaMode renders opaque, and says so once.
TEST(GltfSpheres, AlphaIsIgnoredWithAWarning) {
    TempDir dir;
    GltfBuilder g;
    const int blend = g.material(
        Json::parse(R"({"pbrMetallicRoughness": {"metallicFactor": 0}, "alphaMode": "BLEND"})"));
    for (int i = 0; i < 2; ++i)
        g.node({{"name", "ball" + std::to_string(i)},
                {"translation", {3 * i, 0, 0}},
                {"extensions", {{"VKPATH_sphere", {{"radius", 1}, {"material", blend}}}}}});
    g.node({{"mesh", g.triangle(blend)}});
    g.camera();
    const Loaded loaded = load(g.writeGltf(dir / "spheres.gltf"));
    EXPECT_EQ(lines(loaded.warnings).size(), 1u) << loaded.warnings;
    EXPECT_CONTAINS(
        loaded.warnings,
        "alphaMode is ignored on VKPATH_sphere: spheres are opaque (2 spheres, first: ball0)");
    EXPECT_EQ(loaded.scene.materials.at(loaded.scene.meshes.at(0).material).alphaMode,
              scene::AlphaMode::Blend);
}

TEST(GltfSpheres, NonUniformScaleWarnsAndBadRadiusFails) {
    TempDir dir;
    GltfBuilder stretched;
    stretched.node({{"scale", {1, 8, 1}}, {"extensions", {{"VKPATH_sphere", {{"radius", 1}}}}}});
    const Loaded loaded = load(stretched.writeGltf(dir / "stretched.gltf"));
    EXPECT_EQ(countLinesContaining(loaded.warnings, "non-uniform scale"), 1u);
    EXPECT_FLOAT_EQ(loaded.scene.spheres[0].radius, 2.0f);  // cube root of 8

    GltfBuilder negative;
    negative.node({{"extensions", {{"VKPATH_sphere", {{"radius", -1}}}}}});
    EXPECT_CONTAINS(loadError(negative.writeGltf(dir / "negative.gltf")), "radius");
    GltfBuilder badMaterial;
    badMaterial.node({{"extensions", {{"VKPATH_sphere", {{"radius", 1}, {"material", 3}}}}}});
    EXPECT_CONTAINS(loadError(badMaterial.writeGltf(dir / "material.gltf")), "material");
}

// ---------------------------------------------------------------------------
// VKPATH_environment: the scene's sky
// ---------------------------------------------------------------------------

TEST(GltfEnvironment, ColourStrengthAndRotation) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    g.doc["extensionsUsed"] = {"VKPATH_environment"};
    g.doc["extensions"] = {
        {"VKPATH_environment", {{"color", {0.5, 1, 2}}, {"strength", 3}, {"rotation", 30}}}};
    const Loaded loaded = load(g.writeGltf(dir / "sky.gltf"));
    EXPECT_EQ(countLinesContaining(loaded.warnings, "VKPATH_environment"), 0u);
    ASSERT_TRUE(loaded.scene.environment);
    const scene::Environment& env = *loaded.scene.environment;
    EXPECT_FALSE(env.map);
    expectVec3Near(env.color, {0.5f, 1, 2}, 0);
    EXPECT_FLOAT_EQ(env.strength, 3.0f);
    EXPECT_FLOAT_EQ(env.rotationDegrees, 30.0f);
    EXPECT_TRUE(loaded.scene.features().environment);
}

TEST(GltfEnvironment, MapBesideTheScene) {
    TempDir dir;
    fs::create_directories(dir / "scene" / "maps");
    image::Image map(4, 2);
    for (size_t i = 0; i < map.pixels.size(); ++i) map.pixels[i] = glm::vec3(float(i));
    image::writeExr(dir / "scene" / "maps" / "sky map.exr", map, {});
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    g.doc["extensions"] = {{"VKPATH_environment", {{"uri", "maps/sky%20map.exr"}}}};
    const Loaded loaded = load(g.writeGltf(dir / "scene" / "sky.gltf"));
    ASSERT_TRUE(loaded.scene.environment && loaded.scene.environment->map);
    EXPECT_EQ(loaded.scene.environment->map->pixels, map.pixels);
    EXPECT_FLOAT_EQ(loaded.scene.environment->strength, 1.0f);
    EXPECT_FLOAT_EQ(loaded.scene.environment->rotationDegrees, 0.0f);
}

TEST(GltfEnvironment, BadEnvironmentsAreOneLineErrors) {
    TempDir dir;
    fs::create_directories(dir / "scene");
    image::writeExr(dir / "outside.exr", image::Image(2, 1), {});
    const std::vector<std::pair<Json, std::string>> cases = {
        {Json::object(), "exactly one of 'uri' and 'color'"},
        {{{"uri", "a.exr"}, {"color", {1, 1, 1}}}, "exactly one of 'uri' and 'color'"},
        {{{"uri", "../outside.exr"}}, "leaves the scene's folder"},
        {{{"uri", "missing.exr"}}, "does not exist"},
        {{{"uri", 7}}, "uri is not a string"},
        {{{"color", {1, 1}}}, "color"},
        {{{"color", {1, -1, 1}}}, "color"},
        {{{"color", {1, 1, 1}}, {"strength", -1}}, "strength"},
        {{{"color", {1, 1, 1}}, {"rotation", "north"}}, "rotation"},
    };
    for (const auto& [extension, problem] : cases) {
        SCOPED_TRACE(extension.dump());
        GltfBuilder g;
        g.node({{"mesh", g.triangle()}});
        g.doc["extensions"] = {{"VKPATH_environment", extension}};
        const std::string message = loadError(g.writeGltf(dir / "scene" / "bad.gltf"));
        EXPECT_CONTAINS(message, "VKPATH_environment");
        EXPECT_CONTAINS(message, problem);
    }
}

// ---------------------------------------------------------------------------
// Warnings: never silent, one line per kind
// ---------------------------------------------------------------------------

TEST(GltfWarnings, OneLinePerKind) {
    TempDir dir;
    GltfBuilder g;
    g.doc["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness", "EXT_lights_image_based"};
    g.doc["textures"] = {{{"source", 0}}};
    g.doc["images"] = {{{"uri", "wood.png"}}};
    writeText(dir / "wood.png", "not decoded");
    for (int i = 0; i < 3; ++i)
        g.material(
            {{"name", "textured" + std::to_string(i)},
             {"pbrMetallicRoughness",
              {{"metallicFactor", 0}, {"baseColorTexture", {{"index", 0}}}}},
             {"extensions", {{"KHR_materials_pbrSpecularGlossiness", {{"glossinessFactor", 1}}}}}});
    // Two meshes with degenerate triangles (repeated vertices): 2 + 3 dropped.
    const int positions = g.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    g.node({{"mesh", g.mesh(positions, g.indices({0, 1, 2, 0, 0, 1, 1, 2, 2}, U16), -1, 0)}});
    g.node(
        {{"mesh", g.mesh(positions, g.indices({0, 1, 2, 0, 0, 0, 1, 1, 1, 2, 2, 2}, U16), -1, 1)}});
    g.node({{"mesh", g.triangle(2)}});
    const Loaded loaded = load(g.writeGltf(dir / "warnings.gltf"));
    EXPECT_EQ(loaded.scene.triangleCount(), 3u);

    const std::string prefix = "vkpath: warning: " + (dir / "warnings.gltf").string() + ": ";
    for (const std::string& line : lines(loaded.warnings))
        EXPECT_EQ(line.rfind(prefix, 0), 0u) << line;
    // Three materials use the one image that cannot be decoded: one line, one image.
    EXPECT_EQ(countLinesContaining(loaded.warnings, "images that cannot be decoded (png)"), 1u);
    EXPECT_EQ(countLinesContaining(loaded.warnings, "(1 image, first: image 0 (cannot decode"), 1u);
    EXPECT_EQ(countLinesContaining(loaded.warnings, "'KHR_materials_pbrSpecularGlossiness'"), 1u);
    EXPECT_EQ(countLinesContaining(loaded.warnings, "'EXT_lights_image_based'"), 1u);
    EXPECT_EQ(countLinesContaining(loaded.warnings, "degenerate triangles"), 1u);
    EXPECT_EQ(countLinesContaining(loaded.warnings, "(5 triangles"), 1u);
    EXPECT_EQ(countLinesContaining(loaded.warnings, "default camera"), 1u);
    EXPECT_EQ(lines(loaded.warnings).size(), 5u) << loaded.warnings;
}

TEST(GltfWarnings, RequiredUnsupportedExtensionIsAnError) {
    TempDir dir;
    GltfBuilder g;
    g.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    g.node({{"mesh", g.triangle()}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "draco.gltf")), "KHR_draco_mesh_compression");
    // As Draco files are: accessors without a bufferView (the data is in the
    // compressed extension's own buffer), which tinygltf itself refuses, so
    // the extension must be named before tinygltf reads the file.
    for (auto& accessor : g.doc["accessors"]) accessor.erase("bufferView");
    const std::string error = loadError(g.writeGltf(dir / "draco.gltf"));
    EXPECT_CONTAINS(error, "requires extension 'KHR_draco_mesh_compression'");
    EXPECT_EQ(error.find("bufferView"), std::string::npos) << error;
}

// ---------------------------------------------------------------------------
// Bad input: one test per case, each an InputError naming the file
// ---------------------------------------------------------------------------

TEST(GltfBadInput, MissingFile) {
    TempDir dir;
    EXPECT_CONTAINS(loadError(dir / "absent.gltf"), "no such file");
}

TEST(GltfBadInput, EmptyFile) {
    TempDir dir;
    writeText(dir / "empty.gltf", "");
    EXPECT_CONTAINS(loadError(dir / "empty.gltf"), "empty");
}

TEST(GltfBadInput, TruncatedGltf) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    const fs::path path = g.writeGltf(dir / "whole.gltf");
    const auto bytes = readBytes(path);
    writeBytes(dir / "cut.gltf", bytes.data(), bytes.size() / 2);
    EXPECT_CONTAINS(loadError(dir / "cut.gltf"), "invalid JSON");
}

TEST(GltfBadInput, TruncatedGlb) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    const auto bytes = g.glb();
    for (size_t size : {size_t(6), size_t(16), bytes.size() / 2, bytes.size() - 4}) {
        SCOPED_TRACE(size);
        writeBytes(dir / "cut.glb", bytes.data(), size);
        EXPECT_CONTAINS(loadError(dir / "cut.glb"), "truncated GLB");
    }
}

TEST(GltfBadInput, GlbChunkOverrunsTheFile) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    auto bytes = g.glb();
    // tinygltf checks the BIN chunk against the total length without its
    // 8-byte header: a chunk 4 bytes too long would read past the end.
    const uint32_t jsonLength = bytes[12] | bytes[13] << 8 | bytes[14] << 16 | bytes[15] << 24;
    bytes[20 + jsonLength] += 4;
    writeBytes(dir / "overrun.glb", bytes.data(), bytes.size());
    EXPECT_CONTAINS(loadError(dir / "overrun.glb"), "BIN chunk");
}

TEST(GltfBadInput, InvalidJson) {
    TempDir dir;
    writeText(dir / "bad.gltf", R"({"asset": {"version": "2.0"}, "nodes": [,]})");
    EXPECT_CONTAINS(loadError(dir / "bad.gltf"), "invalid JSON");
}

// Found by gltf_fuzz: a number beyond double's range is a JSON error too,
// not an internal failure.
TEST(GltfBadInput, NumberOutOfRange) {
    TempDir dir;
    writeText(dir / "huge.gltf", R"({"asset": {"version": "2.0"}, "x": 1e309})");
    EXPECT_CONTAINS(loadError(dir / "huge.gltf"), "invalid JSON");
}

TEST(GltfBadInput, NotGltfVersion2) {
    TempDir dir;
    writeText(dir / "old.gltf", R"({"asset": {"version": "1.0"}})");
    EXPECT_CONTAINS(loadError(dir / "old.gltf"), "version 1.0");
}

TEST(GltfBadInput, MissingBufferUri) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "nouri.gltf", GltfBuilder::Buffer::None)),
                    "buffer 0 has no uri");
    // A data URI tinygltf cannot decode (it would look for a file of that name).
    Json doc = g.trimmed();
    doc["buffers"] = Json::array(
        {{{"byteLength", g.bin.size()}, {"uri", "data:text/csv;base64," + base64(g.bin)}}});
    writeText(dir / "csv.gltf", doc.dump());
    EXPECT_CONTAINS(loadError(dir / "csv.gltf"), "buffer 0: data URI");
}

TEST(GltfBadInput, BufferFileMissing) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    const fs::path path = g.writeGltf(dir / "scene.gltf", GltfBuilder::Buffer::External);
    fs::remove(dir / "scene.bin");
    EXPECT_CONTAINS(loadError(path), "does not exist");
}

TEST(GltfBadInput, UriEscapingTheFolder) {
    TempDir dir;
    fs::create_directories(dir / "scene");
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    writeBytes(dir / "outside.bin", g.bin.data(),
               g.bin.size());  // the file exists: only the path is wrong
    fs::create_symlink("../outside.bin", dir / "scene" / "link.bin");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"../outside.bin", "leaves the scene's folder"},
        {"sub/../../outside.bin", "leaves the scene's folder"},
        {"%2E%2E/outside.bin", "leaves the scene's folder"},
        {(dir / "outside.bin").string(), "absolute"},
        {"file:///etc/passwd", "scheme"},
        {"link.bin", "through a link"},
    };
    for (const auto& [uri, problem] : cases) {
        SCOPED_TRACE(uri);
        Json doc = g.doc;
        doc["buffers"] = Json::array({{{"byteLength", g.bin.size()}, {"uri", uri}}});
        writeText(dir / "scene" / "escape.gltf", doc.dump());
        EXPECT_CONTAINS(loadError(dir / "scene" / "escape.gltf"), problem);
    }
    // An image URI is held to the same rule.
    Json doc = g.doc;
    doc["buffers"] =
        Json::array({{{"byteLength", g.bin.size()},
                      {"uri", "data:application/octet-stream;base64," + base64(g.bin)}}});
    doc["images"] = Json::array({{{"uri", "../outside.bin"}}});
    writeText(dir / "scene" / "image.gltf", doc.dump());
    EXPECT_CONTAINS(loadError(dir / "scene" / "image.gltf"), "image 0");
}

TEST(GltfBadInput, AccessorCountOutOfRange) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    g.doc["accessors"][0]["count"] = 4;  // the bufferView holds 3 positions
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "count.gltf")), "overruns its bufferView");
    // Without a bufferView an accessor is zeros: a huge count must not allocate.
    g.doc["accessors"][0].erase("bufferView");
    g.doc["accessors"][0]["count"] = 1u << 24;
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "zeros.gltf")),
                    "has no bufferView and count 16777216");
}

TEST(GltfBadInput, AccessorOffsetOutOfRange) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    g.doc["accessors"][0]["byteOffset"] = 4;
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "offset.gltf")), "overruns its bufferView");
    g.doc["accessors"][0]["byteOffset"] = 1u << 31;
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "offset.gltf")), "overruns its bufferView");
}

TEST(GltfBadInput, BufferViewOutOfRange) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    g.doc["bufferViews"][1]["byteLength"] = 4096;
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "view.gltf")), "overruns buffer 0");
}

TEST(GltfBadInput, IndexOutOfRange) {
    TempDir dir;
    GltfBuilder g;
    g.node(
        {{"mesh", g.mesh(g.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), g.indices({0, 1, 3}, U16))}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "index.gltf")), "index 3 is out of range");
}

TEST(GltfBadInput, WrongAccessorType) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}});
    g.doc["accessors"][0]["componentType"] = U16;
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "type.gltf")), "must be FLOAT VEC3");
}

TEST(GltfBadInput, NanPositions) {
    TempDir dir;
    GltfBuilder g;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    g.node({{"mesh", g.mesh(g.vec3s({{0, 0, 0}, {nan, 0, 0}, {0, 1, 0}}))}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "nan.gltf")), "not finite");
}

TEST(GltfBadInput, ModeNotTriangles) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.mesh(g.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), -1, -1, -1, 1)}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "lines.gltf")), "mode 1 (LINES) is not supported");
}

// TRIANGLE_STRIP (5) and TRIANGLE_FAN (6) become the triangles glTF 2.0
// 3.7.2.1 defines, with every triangle's winding kept counter-clockwise (all
// face +Z here), indexed or not.
TEST(GltfLayouts, TriangleStripsAndFansBecomeTriangles) {
    TempDir dir;
    struct Case {
        int mode;
        std::vector<glm::vec3> positions;
        std::vector<glm::uvec3> triangles;
    };
    const Case cases[] = {
        // A strip along x, zig-zagging between y = 1 (even vertices) and y = 0 (odd).
        {5,
         {{0, 1, 0}, {0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {2, 1, 0}, {2, 0, 0}},
         {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}, {3, 5, 4}}},
        // A fan around the origin.
        {6,
         {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}},
         {{1, 2, 0}, {2, 3, 0}, {3, 4, 0}}},
    };
    for (const Case& c : cases) {
        for (const bool indexed : {false, true}) {
            GltfBuilder g;
            std::vector<uint32_t> order(c.positions.size());
            for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
            const int positions = g.vec3s(c.positions);
            g.node({{"mesh",
                     g.mesh(positions, indexed ? g.indices(order, U16) : -1, -1, -1, c.mode)}});
            const scene::Scene s = load(g.writeGltf(dir / "strip.gltf")).scene;
            ASSERT_EQ(s.meshes.size(), 1u) << c.mode;
            EXPECT_EQ(s.meshes[0].triangles, c.triangles)
                << "mode " << c.mode << (indexed ? " indexed" : "");
            for (const glm::uvec3& t : s.meshes[0].triangles) {
                const glm::vec3 n =
                    glm::cross(s.meshes[0].positions[t.y] - s.meshes[0].positions[t.x],
                               s.meshes[0].positions[t.z] - s.meshes[0].positions[t.x]);
                EXPECT_GT(n.z, 0.0f) << "mode " << c.mode << ": a triangle faces away";
            }
        }
    }
}

TEST(GltfBadInput, UnknownAlphaModeOrNegativeCutoff) {
    TempDir dir;
    for (const auto& [material, phrase] :
         {std::pair{R"({"name": "glassy", "alphaMode": "TRANSLUCENT"})",
                    "material 'glassy': alphaMode 'TRANSLUCENT' is not OPAQUE, MASK or BLEND"},
          std::pair{R"({"name": "cut", "alphaMode": "MASK", "alphaCutoff": -0.5})",
                    "material 'cut': alphaCutoff -0.5 is not a finite number >= 0"}}) {
        GltfBuilder g;
        g.node({{"mesh", g.triangle(g.material(Json::parse(material)))}});
        const std::string error = loadError(g.writeGltf(dir / "alpha.gltf"));
        EXPECT_CONTAINS(error, phrase);
        EXPECT_CONTAINS(error, "alpha.gltf");
    }
}

TEST(GltfBadInput, NoGeometry) {
    TempDir dir;
    GltfBuilder g;
    g.doc["cameras"] = {perspective("only", 0.5)};
    g.node({{"camera", 0}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "empty-scene.gltf")), "no geometry");
    // Only degenerate triangles is no geometry either.
    GltfBuilder flat;
    flat.node({{"mesh", flat.mesh(flat.vec3s({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}))}});
    EXPECT_CONTAINS(loadError(flat.writeGltf(dir / "flat.gltf")), "no geometry");
}

TEST(GltfBadInput, ZeroFovCamera) {
    TempDir dir;
    GltfBuilder g;
    g.doc["cameras"] = {perspective("zero", 0.0)};
    g.node({{"mesh", g.triangle()}});
    g.node({{"camera", 0}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "fov.gltf")), "yfov 0 is not in (0, pi)");
}

TEST(GltfBadInput, NodeWithTwoParents) {
    TempDir dir;
    GltfBuilder g;
    const int shared = g.node({{"mesh", g.triangle()}}, false);
    g.node({{"children", {shared}}});
    g.node({{"children", {shared}}});
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "dag.gltf")), "more than one parent");
}

TEST(GltfBadInput, NodeCycleIsNotARoot) {
    TempDir dir;
    GltfBuilder g;
    g.node({{"mesh", g.triangle()}, {"children", {1}}});
    g.node({{"children", {0}}}, false);
    EXPECT_CONTAINS(loadError(g.writeGltf(dir / "cycle.gltf")), "not a root");
}

}  // namespace
