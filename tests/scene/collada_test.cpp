// The Scotty3D COLLADA importer. Every shared scene loads; counts, lamps,
// lights and the camera framing are checked against numbers worked out from
// the files by hand or with a separate script (not from the loader), winding
// and normals under mirroring and non-uniform scale against small documents
// written here, and each kind of bad input against InputError.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "input_error.h"
#include "scene/camera.h"
#include "scene/collada_loader.h"
#include "scene/load.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// Small documents
// ---------------------------------------------------------------------------

// A valid Y_UP scene: one triangle (optionally with per-corner normals), a
// diffuse material, a camera. Tests swap pieces to make it bad or add to it.
struct Doc {
    std::string upAxis = "Y_UP";
    std::string unitMeter = "1";
    std::string positions = "0 0 0  1 0 0  0 1 0";
    std::string normals;  // per-corner NORMAL source (x y z per corner) when not empty
    std::string vcount = "3";
    std::string p = "0 1 2";
    std::string geometryUrl = "#tri";
    std::string nodeMatrix = "1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1";
    std::string xfov = "50";
    bool geometryNode = true;
    std::string extraEffects, extraMaterials, extraGeometries, extraNodes, lights;
};

size_t tokenCount(const std::string& s) {
    size_t n = 0;
    bool inToken = false;
    for (char c : s) {
        const bool space = std::isspace(static_cast<unsigned char>(c)) != 0;
        n += !space && !inToken;
        inToken = !space;
    }
    return n;
}

std::string effect(const std::string& id, const std::string& diffuse, const std::string& cmu = "") {
    std::string xml = "<effect id=\"" + id +
                      "-effect\"><profile_COMMON><technique sid=\"common\">"
                      "<phong><diffuse><color>" +
                      diffuse +
                      " 1</color></diffuse></phong>"
                      "</technique></profile_COMMON>";
    if (!cmu.empty()) xml += "<extra><technique profile=\"CMU462\">" + cmu + "</technique></extra>";
    return xml + "</effect>";
}

std::string material(const std::string& id) {
    return "<material id=\"" + id + "\" name=\"" + id + "\"><instance_effect url=\"#" + id +
           "-effect\"/></material>";
}

std::string bind(const std::string& materialId) {
    return "<bind_material><technique_common><instance_material symbol=\"" + materialId +
           "\" target=\"#" + materialId + "\"/></technique_common></bind_material>";
}

std::string xml(const Doc& d) {
    const bool hasNormals = !d.normals.empty();
    std::string s = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter=")" +
                    d.unitMeter + R"("/><up_axis>)" + d.upAxis + R"(</up_axis></asset>
  <library_cameras><camera id="cam" name="cam"><optics><technique_common><perspective>
    <xfov>)" + d.xfov +
                    R"(</xfov><aspect_ratio>1.5</aspect_ratio>
  </perspective></technique_common></optics></camera></library_cameras>
  <library_lights>)" +
                    d.lights + R"(</library_lights>
  <library_effects>)" +
                    effect("white", "0.8 0.8 0.8") + d.extraEffects + R"(</library_effects>
  <library_materials>)" +
                    material("white") + d.extraMaterials + R"(</library_materials>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="tri-positions"><float_array id="tri-positions-array" count=")" +
                    std::to_string(tokenCount(d.positions)) + "\">" + d.positions +
                    R"(</float_array>
        <technique_common><accessor source="#tri-positions-array" count=")" +
                    std::to_string(tokenCount(d.positions) / 3) +
                    R"(" stride="3"/></technique_common>
      </source>)";
    if (hasNormals)
        s += R"(<source id="tri-normals"><float_array id="tri-normals-array">)" + d.normals +
             R"(</float_array><technique_common><accessor source="#tri-normals-array" count=")" +
             std::to_string(tokenCount(d.normals) / 3) +
             R"(" stride="3"/></technique_common></source>)";
    s += R"(<vertices id="tri-vertices">
        <input semantic="POSITION" source="#tri-positions"/></vertices>
      <polylist material="white" count=")" +
         std::to_string(tokenCount(d.vcount)) + R"(">
        <input semantic="VERTEX" source="#tri-vertices" offset="0"/>)";
    if (hasNormals) s += R"(<input semantic="NORMAL" source="#tri-normals" offset="1"/>)";
    s += "<vcount>" + d.vcount + "</vcount><p>" + d.p + R"(</p>
      </polylist>
    </mesh></geometry>)" +
         d.extraGeometries + R"(
  </library_geometries>
  <library_visual_scenes><visual_scene id="Scene" name="Scene">
    <node id="Camera" name="Camera"><matrix>1 0 0 0 0 1 0 0 0 0 1 5 0 0 0 1</matrix>
      <instance_camera url="#cam"/></node>)";
    if (d.geometryNode)
        s += "<node id=\"Tri\" name=\"Tri\"><matrix>" + d.nodeMatrix +
             "</matrix><instance_geometry url=\"" + d.geometryUrl + "\">" + bind("white") +
             "</instance_geometry></node>";
    s += d.extraNodes + R"(
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
    return s;
}

// A directory of its own per test, removed afterwards.
using test::TempDir;

scene::Scene loadQuiet(const fs::path& path, std::vector<std::string>* warnings = nullptr) {
    std::vector<std::string> sink;
    return scene::loadCollada(path, {}, warnings ? warnings : &sink);
}

bool anyContains(const std::vector<std::string>& lines, const std::string& text) {
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

glm::vec3 faceNormal(const scene::Mesh& mesh, size_t triangle) {
    const glm::uvec3 t = mesh.triangles[triangle];
    return glm::normalize(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                     mesh.positions[t.z] - mesh.positions[t.x]));
}

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance) {
    EXPECT_NEAR(actual.x, expected.x, tolerance);
    EXPECT_NEAR(actual.y, expected.y, tolerance);
    EXPECT_NEAR(actual.z, expected.z, tolerance);
}

size_t emissiveMeshCount(const scene::Scene& s) {
    size_t n = 0;
    for (const scene::Mesh& m : s.meshes) n += s.materials[m.material].emissive();
    return n;
}

size_t emissiveSphereCount(const scene::Scene& s) {
    size_t n = 0;
    for (const scene::Sphere& sp : s.spheres) n += s.materials[sp.material].emissive();
    return n;
}

// ---------------------------------------------------------------------------
// Every shared scene
// ---------------------------------------------------------------------------

std::vector<std::string> sharedDaeFiles() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(test::sharedScene(""), ec))
        if (entry.path().extension() == ".dae") names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Without the folder, ColladaSharedScene has no instances: this test says why.
TEST(ColladaShared, FindsTheScenes) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    // 23 files in <scenes>/scotty3d; a partial checkout must not pass silently.
    EXPECT_GE(sharedDaeFiles().size(), 23u);
}

class ColladaSharedScene : public testing::TestWithParam<std::string> {};

TEST_P(ColladaSharedScene, LoadsAndIsConsistent) {
    const scene::Scene s = loadQuiet(test::sharedScene(GetParam()));
    ASSERT_FALSE(s.meshes.empty() && s.spheres.empty());
    for (const scene::Mesh& m : s.meshes) {
        ASSERT_LT(m.material, s.materials.size());
        EXPECT_FALSE(m.triangles.empty()) << m.name;
        EXPECT_TRUE(m.normals.empty() || m.normals.size() == m.positions.size()) << m.name;
        for (const glm::uvec3& t : m.triangles)
            for (int i = 0; i < 3; ++i) ASSERT_LT(t[i], m.positions.size()) << m.name;
        for (const glm::vec3& p : m.positions)
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
        for (const glm::vec3& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f) << m.name;
    }
    for (const scene::Sphere& sp : s.spheres) {
        ASSERT_LT(sp.material, s.materials.size());
        EXPECT_GT(sp.radius, 0.0f);
    }
    // Every scene of the set is lit by something.
    EXPECT_TRUE(emissiveMeshCount(s) + emissiveSphereCount(s) + s.pointLights.size() +
                    s.spotLights.size() + s.directionalLights.size() + s.environment.has_value() >
                0);
    // The framed camera is a valid pinhole outside the scene.
    EXPECT_NO_THROW(scene::makeGpuCamera(s.camera, 64, 48));
    EXPECT_GT(glm::length(s.camera.position - s.camera.target), 0.0f);
    EXPECT_NO_THROW(s.features());
}

std::string parameterName(const testing::TestParamInfo<std::string>& info) {
    std::string name = fs::path(info.param).stem().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(AllFiles, ColladaSharedScene, testing::ValuesIn(sharedDaeFiles()),
                         parameterName);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ColladaSharedScene);

// Counts from a separate Python script over the files: sum of (vcount - 2)
// over the polylists of every instanced geometry, minus triangles whose
// transformed corners are collinear (plane1024/16384 have a node with an
// all-zero matrix: its 8 triangles collapse to a point), plus 2 for an area
// light without a lamp mesh (floating).
TEST(ColladaShared, ExactCounts) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    struct Expected {
        const char* file;
        size_t triangles, meshes, spheres;
    };
    for (const Expected& e :
         {Expected{"CBbunny.dae", 28576 + 6 * 2, 7, 0}, Expected{"bunny.dae", 28576 + 5120, 2, 0},
          Expected{"plane4.dae", 8, 1, 0}, Expected{"plane64.dae", 128, 1, 0},
          Expected{"plane1024.dae", 2048, 1, 0}, Expected{"cubeWithLight.dae", 6 * 2, 1, 0},
          Expected{"trigs10.dae", 10, 10, 0}, Expected{"floating.dae", 2 + 2 + 2, 3, 0},
          Expected{"sphere7_glass.dae", 0, 0, 7}, Expected{"carim_mirror.dae", 8, 1, 4}}) {
        SCOPED_TRACE(e.file);
        const scene::Scene s = loadQuiet(test::sharedScene(e.file));
        EXPECT_EQ(s.triangleCount(), e.triangles);
        EXPECT_EQ(s.meshes.size(), e.meshes);
        EXPECT_EQ(s.spheres.size(), e.spheres);
    }
}

TEST(ColladaShared, DegenerateTrianglesAreDroppedWithOneWarning) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    std::vector<std::string> warnings;
    loadQuiet(test::sharedScene("plane1024.dae"), &warnings);
    const auto count = std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) {
        return w.find("degenerate") != std::string::npos;
    });
    EXPECT_EQ(count, 1);
    EXPECT_TRUE(anyContains(warnings, "dropped 8 degenerate"));
}

TEST(ColladaShared, BunnyKeepsSmoothNormalsAndFlatMeshesDropThem) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadQuiet(test::sharedScene("CBbunny.dae"));
    size_t withNormals = 0;
    for (const scene::Mesh& m : s.meshes) {
        if (m.triangles.size() == 28576) {
            // Smooth normals: 14290 positions, shared where a position has
            // one normal, so far fewer vertices than 3 per triangle.
            EXPECT_EQ(m.normals.size(), m.positions.size());
            EXPECT_LT(m.positions.size(), 28576u);
            ++withNormals;
        } else {
            // The box's walls are flat: 4 shared corners, no normals.
            EXPECT_TRUE(m.normals.empty()) << m.name;
            EXPECT_EQ(m.positions.size(), 4u) << m.name;
        }
    }
    EXPECT_EQ(withNormals, 1u);
}

// ---------------------------------------------------------------------------
// CBspheres: spheres, materials, the lamp, the camera
// ---------------------------------------------------------------------------

TEST(ColladaCBspheres, SpheresMaterialsAndOneLamp) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    std::vector<std::string> warnings;
    const scene::Scene s = loadQuiet(test::sharedScene("CBspheres.dae"), &warnings);
    ASSERT_EQ(s.spheres.size(), 2u);
    // Sphere1 (glass, "refract") at Z-up (-0.4, 0.3, 0.3): Y-up (0.4, 0.3, 0.3).
    // Sphere2 (mirror, "chrome") at Z-up (0.4, -0.3, 0.3): Y-up (-0.4, 0.3, -0.3).
    const scene::Sphere& glass = s.spheres[0];
    const scene::Sphere& mirror = s.spheres[1];
    expectNear(glass.center, {0.4f, 0.3f, 0.3f}, 1e-6f);
    expectNear(mirror.center, {-0.4f, 0.3f, -0.3f}, 1e-6f);
    EXPECT_FLOAT_EQ(glass.radius, 0.3f);
    EXPECT_FLOAT_EQ(mirror.radius, 0.3f);
    EXPECT_EQ(s.materials[glass.material].kind, scene::MaterialKind::Dielectric);
    EXPECT_FLOAT_EQ(s.materials[glass.material].ior, 1.45f);
    EXPECT_EQ(s.materials[mirror.material].kind, scene::MaterialKind::Mirror);
    expectNear(s.materials[mirror.material].reflectance, glm::vec3(1.0f), 0.0f);

    // The lamp is an area light and a mesh: exactly one emitter, the mesh,
    // with the radiance both give (10), and no punctual light beside it.
    EXPECT_EQ(emissiveMeshCount(s), 1u);
    EXPECT_EQ(emissiveSphereCount(s), 0u);
    EXPECT_TRUE(s.pointLights.empty());
    EXPECT_TRUE(s.spotLights.empty());
    EXPECT_TRUE(s.directionalLights.empty());
    EXPECT_FALSE(s.environment.has_value());
    EXPECT_EQ(s.triangleCount(), 12u);  // six walls, ceiling and lamp of two triangles
    for (const scene::Mesh& m : s.meshes) {
        if (!s.materials[m.material].emissive()) continue;
        EXPECT_EQ(m.triangles.size(), 2u);
        expectNear(s.materials[m.material].emission, glm::vec3(10.0f), 0.0f);
        // The lamp lights the room below it.
        for (size_t t = 0; t < m.triangles.size(); ++t)
            expectNear(faceNormal(m, t), {0, -1, 0}, 1e-5f);
    }
    EXPECT_TRUE(anyContains(warnings, "area light 'Light'"));

    const scene::FeatureSummary f = s.features();
    EXPECT_TRUE(f.triangles && f.spheres && f.diffuse && f.mirror && f.glass && f.emissiveSurfaces);
    EXPECT_FALSE(f.pointLights || f.spotLights || f.directionalLights || f.environment);
}

TEST(ColladaCBspheres, CameraFramedBySourceRule) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadQuiet(test::sharedScene("CBspheres.dae"));
    // SOURCE.md's rule by hand. Bounds (Y-up): the walls span x in [-1, 1],
    // y in [0, 1.5], z in [-1, 1]; the spheres (radius 0.3 at y = 0.3) and
    // the lamp lie inside. Target = (0, 0.75, 0), r = 1.5 |(2, 1.5, 2)|.
    const float r = 1.5f * std::sqrt(2.0f * 2.0f + 1.5f * 1.5f + 2.0f * 2.0f);
    // Camera node (row-major) [-1 0 0 0; 0 0 1 3; 0 1 0 0]: M (0,0,-1,1) =
    // (0, 2, 0) Z-up, (0, 0, 2) Y-up, so d = (0, 0, 1): phi = 90 degrees,
    // theta = 0, position = target + r (0, 0, 1).
    expectNear(s.camera.target, {0.0f, 0.75f, 0.0f}, 1e-5f);
    expectNear(s.camera.position, {0.0f, 0.75f, r}, 1e-4f);
    expectNear(s.camera.up, {0, 1, 0}, 0.0f);
    EXPECT_NEAR(s.camera.xfovDegrees, 49.13434f, 1e-4f);
    EXPECT_NEAR(s.camera.aspect, 1.333333f, 1e-6f);
    // The node's own translation, (0, 3, 0) Z-up, is (0, 0, 3) Y-up: a
    // camera on the floor. The framed one is halfway up the room.
    EXPECT_GT(s.camera.position.y, 0.5f);
    EXPECT_NEAR(s.camera.position.y, s.camera.target.y, 1e-5f);
}

TEST(ColladaShared, CBbunnyCameraLooksIntoTheOpenSide) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadQuiet(test::sharedScene("CBbunny.dae"));
    // Camera node [1 0 0 0; 0 0 -1 -3; 0 1 0 0]: M (0,0,-1,1) = (0, -2, 0)
    // Z-up = (0, 0, -2) Y-up: d = (0, 0, -1). The box is turned so its back
    // wall is at z = +1 and the camera looks in from -z.
    const float r = 1.5f * std::sqrt(2.0f * 2.0f + 1.5f * 1.5f + 2.0f * 2.0f);
    expectNear(s.camera.position, {0.0f, 0.75f, -r}, 1e-4f);
    EXPECT_NEAR(s.camera.aspect, 1.777778f, 1e-6f);
}

// ---------------------------------------------------------------------------
// Lights
// ---------------------------------------------------------------------------

TEST(ColladaLights, CBemptyPointLightBesideTheLampIsDropped) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    std::vector<std::string> warnings;
    const scene::Scene s = loadQuiet(test::sharedScene("CBempty.dae"), &warnings);
    EXPECT_TRUE(s.pointLights.empty());
    EXPECT_EQ(emissiveMeshCount(s), 1u);
    EXPECT_TRUE(anyContains(warnings, "point light 'Light'"));
}

TEST(ColladaLights, AreaLightWithoutLampBecomesAQuadFacingItsDirection) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadQuiet(test::sharedScene("floating.dae"));
    // Area node: identity rotation at Z-up (0, 0, 1): centre (0, 1, 0) Y-up,
    // unit square, emitting along local -Z = Z-up down = Y-up (0, -1, 0).
    ASSERT_EQ(emissiveMeshCount(s), 1u);
    for (const scene::Mesh& m : s.meshes) {
        if (!s.materials[m.material].emissive()) continue;
        ASSERT_EQ(m.triangles.size(), 2u);
        float area = 0;
        glm::vec3 center(0.0f);
        for (size_t t = 0; t < 2; ++t) {
            expectNear(faceNormal(m, t), {0, -1, 0}, 1e-6f);
            const glm::uvec3 tri = m.triangles[t];
            area += 0.5f * glm::length(glm::cross(m.positions[tri.y] - m.positions[tri.x],
                                                  m.positions[tri.z] - m.positions[tri.x]));
        }
        for (const glm::vec3& p : m.positions) center += p / float(m.positions.size());
        EXPECT_NEAR(area, 1.0f, 1e-6f);
        expectNear(center, {0, 1, 0}, 1e-6f);
        expectNear(s.materials[m.material].emission, glm::vec3(1.0f), 0.0f);
        expectNear(s.materials[m.material].reflectance, glm::vec3(0.0f), 0.0f);
    }
}

TEST(ColladaLights, PointLightIntensityMatchesIrradianceAtTheSceneCentre) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadQuiet(test::sharedScene("plane4.dae"));
    // Lamp node translation Z-up (-1, 1, 1) = Y-up (1, 1, 1); the plane is
    // centred on the origin, so d^2 = 3 and colour 1 becomes 3 W/sr.
    ASSERT_EQ(s.pointLights.size(), 1u);
    expectNear(s.pointLights[0].position, {1, 1, 1}, 1e-6f);
    expectNear(s.pointLights[0].intensity, glm::vec3(3.0f), 1e-5f);
}

TEST(ColladaLights, DirectionalAndAmbient) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadQuiet(test::sharedScene("sphere_diffuse.dae"));
    // Directional node columns (Z-up): third column (0.5, 0.5, 0.7071068);
    // travelling along -it = (-0.5, -0.5, -0.7071) Z-up = (0.5, -0.7071, -0.5) Y-up.
    ASSERT_EQ(s.directionalLights.size(), 1u);
    expectNear(s.directionalLights[0].direction, {0.5f, -0.7071068f, -0.5f}, 1e-6f);
    expectNear(s.directionalLights[0].irradiance, glm::vec3(1.0f), 0.0f);
    // The "Hemi" ambient light (colour 1) becomes a constant environment.
    ASSERT_TRUE(s.environment.has_value());
    expectNear(s.environment->color, glm::vec3(1.0f), 0.0f);
    EXPECT_FALSE(s.environment->map.has_value());
}

// A lamp described twice where the two disagree: area light radiance 3, lamp
// mesh radiance 10 (a 1 x 1 square at y = 1 facing down).
Doc lampDoc(const std::string& lampP) {
    Doc d;
    d.extraEffects =
        effect("lamp", "0.8 0.8 0.8", "<emission><radiance>10 10 10</radiance></emission>");
    d.extraMaterials = material("lamp");
    d.extraGeometries = R"(<geometry id="lamp-mesh" name="lamp"><mesh>
        <source id="lamp-positions"><float_array id="lamp-positions-array" count="12">
          -0.5 1 -0.5  0.5 1 -0.5  0.5 1 0.5  -0.5 1 0.5</float_array>
          <technique_common><accessor source="#lamp-positions-array" count="4" stride="3"/>
          </technique_common></source>
        <vertices id="lamp-vertices">
          <input semantic="POSITION" source="#lamp-positions"/></vertices>
        <polylist material="lamp" count="1">
          <input semantic="VERTEX" source="#lamp-vertices" offset="0"/>
          <vcount>4</vcount><p>)" +
                        lampP + R"(</p></polylist></mesh></geometry>)";
    d.lights = R"(<light id="area" name="area"><technique_common><point><color>3 3 3</color>
        </point></technique_common><extra><technique profile="CMU462"><area><color>3 3 3</color>
        </area></technique></extra></light>)";
    // Local -Z turned to -Y (columns (1,0,0), (0,0,-1), (0,1,0)), at y = 1.
    d.extraNodes = R"(<node id="Area" name="Area">
        <matrix>1 0 0 0  0 0 1 1  0 -1 0 0  0 0 0 1</matrix>
        <instance_light url="#area"/></node>
      <node id="Lamp" name="Lamp"><instance_geometry url="#lamp-mesh">)" +
                   bind("lamp") + "</instance_geometry></node>";
    return d;
}

TEST(ColladaLights, DisagreeingLampTakesTheAreaLightRadiance) {
    TempDir dir;
    std::vector<std::string> warnings;
    const scene::Scene s = loadQuiet(dir.write("lamp.dae", xml(lampDoc("0 1 2 3"))), &warnings);
    ASSERT_EQ(emissiveMeshCount(s), 1u);  // no quad beside the lamp
    EXPECT_EQ(s.triangleCount(), 1u + 2u);
    for (const scene::Mesh& m : s.meshes)
        if (s.materials[m.material].emissive()) {
            expectNear(s.materials[m.material].emission, glm::vec3(3.0f), 0.0f);
            expectNear(faceNormal(m, 0), {0, -1, 0}, 1e-6f);
        }
    EXPECT_TRUE(anyContains(warnings, "disagree"));
}

TEST(ColladaLights, LampFacingAwayFromItsAreaLightIsTurned) {
    TempDir dir;
    const scene::Scene s = loadQuiet(dir.write("lamp.dae", xml(lampDoc("3 2 1 0"))));
    ASSERT_EQ(emissiveMeshCount(s), 1u);
    for (const scene::Mesh& m : s.meshes)
        if (s.materials[m.material].emissive())
            for (size_t t = 0; t < m.triangles.size(); ++t)
                expectNear(faceNormal(m, t), {0, -1, 0}, 1e-6f);
}

// ---------------------------------------------------------------------------
// Transforms: winding and normals
// ---------------------------------------------------------------------------

TEST(ColladaTransforms, MirroringNodeFlipsWindingAndKeepsFacing) {
    TempDir dir;
    Doc d;
    // Triangle (0,0,0), (1,0,0), (0,1,0): counter-clockwise seen from +Z.
    // Corner normals tilted towards +X so they are kept (not flat).
    d.normals = "0.6 0 0.8  0.6 0 0.8  0.6 0 0.8";
    d.p = "0 0 1 1 2 2";
    d.nodeMatrix = "-1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1";  // mirror x
    const scene::Scene s = loadQuiet(dir.write("mirror.dae", xml(d)));
    ASSERT_EQ(s.meshes.size(), 1u);
    const scene::Mesh& m = s.meshes[0];
    ASSERT_EQ(m.triangles.size(), 1u);
    // Mirrored in x the triangle still faces +Z, so the winding must flip.
    expectNear(faceNormal(m, 0), {0, 0, 1}, 1e-6f);
    // Inverse transpose of diag(-1, 1, 1) on (0.6, 0, 0.8): (-0.6, 0, 0.8).
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (const glm::vec3& n : m.normals) expectNear(n, {-0.6f, 0.0f, 0.8f}, 1e-6f);
    for (const glm::vec3& p : m.positions) EXPECT_LE(p.x, 0.0f);
}

// A geometry that three nodes place with the same material binding is kept
// once in its own space and placed by instances with --instancing on, as a
// glTF mesh is (tests/scene/gltf_instancing_test.cpp); copied per node with
// off. A node that binds it another material gets a copy of its own.
TEST(ColladaTransforms, AGeometryPlacedThriceIsKeptOnceWhenInstancingIsOn) {
    TempDir dir;
    Doc d;
    d.extraEffects = effect("red", "0.8 0.1 0.1");
    d.extraMaterials = material("red");
    auto node = [](const std::string& name, const std::string& matrix, const std::string& mat) {
        return "<node id=\"" + name + "\" name=\"" + name + "\"><matrix>" + matrix +
               "</matrix><instance_geometry url=\"#tri\">" + bind(mat) +
               "</instance_geometry></node>";
    };
    d.extraNodes = node("A", "1 0 0 2  0 1 0 0  0 0 1 0  0 0 0 1", "white") +
                   node("B", "-1 0 0 4  0 1 0 0  0 0 1 0  0 0 0 1", "white") +
                   node("C", "1 0 0 6  0 1 0 0  0 0 1 0  0 0 0 1", "red");
    const fs::path file = dir.write("placed.dae", xml(d));
    std::vector<std::string> warnings;
    scene::LoadOptions on;
    on.instancing = scene::Instancing::On;
    const scene::Scene s = scene::loadCollada(file, on, &warnings);
    size_t instanced = 0;
    for (const scene::Mesh& m : s.meshes) instanced += m.instanced;
    EXPECT_EQ(instanced, 1u);
    EXPECT_EQ(s.meshes.size(), 2u);     // the white triangle once, the red one copied
    ASSERT_EQ(s.instances.size(), 3u);  // Tri, A and B
    EXPECT_EQ(s.instances[1].objectToWorld[3], glm::dvec4(2, 0, 0, 1));
    EXPECT_EQ(s.instances[2].objectToWorld[0], glm::dvec4(-1, 0, 0, 0));
    EXPECT_EQ(s.drawnTriangleCount(), 4u);
    const scene::Scene copied = scene::loadCollada(file, {}, &warnings);
    EXPECT_TRUE(copied.instances.empty());
    EXPECT_EQ(copied.meshes.size(), 4u);
    EXPECT_EQ(copied.drawnTriangleCount(), 4u);
    // The scene's box holds the placed copies alike.
    EXPECT_EQ(s.geometryBounds().lo, copied.geometryBounds().lo);
    EXPECT_EQ(s.geometryBounds().hi, copied.geometryBounds().hi);
}

TEST(ColladaTransforms, NonUniformScaleUsesTheInverseTranspose) {
    TempDir dir;
    Doc d;
    d.normals = "0.6 0 0.8  0.6 0 0.8  0.6 0 0.8";
    d.p = "0 0 1 1 2 2";
    d.nodeMatrix = "2 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1";
    const scene::Scene s = loadQuiet(dir.write("scaled.dae", xml(d)));
    ASSERT_EQ(s.meshes.size(), 1u);
    // diag(1/2, 1, 1) (0.6, 0, 0.8) = (0.3, 0, 0.8), normalised.
    const glm::vec3 expected = glm::normalize(glm::vec3(0.3f, 0.0f, 0.8f));
    for (const glm::vec3& n : s.meshes[0].normals) expectNear(n, expected, 1e-6f);
    expectNear(faceNormal(s.meshes[0], 0), {0, 0, 1}, 1e-6f);
}

TEST(ColladaTransforms, ZUpTurnsToYUpAndPolygonsAreFans) {
    TempDir dir;
    Doc d;
    d.upAxis = "Z_UP";
    // A pentagon in the Z-up ground plane z = 0, counter-clockwise from +Z.
    d.positions = "0 0 0  2 0 0  3 1 0  1 3 0  -1 1 0";
    d.vcount = "5";
    d.p = "0 1 2 3 4";
    const scene::Scene s = loadQuiet(dir.write("zup.dae", xml(d)));
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.triangleCount(), 3u);  // a fan of 5 - 2
    // x' = -x, y' = z, z' = y: the ground stays ground (y' = 0), facing +Y.
    for (const glm::vec3& p : s.meshes[0].positions) EXPECT_FLOAT_EQ(p.y, 0.0f);
    expectNear(s.meshes[0].positions[1], {-2, 0, 0}, 0.0f);
    expectNear(s.meshes[0].positions[3], {-1, 0, 3}, 0.0f);
    for (size_t t = 0; t < 3; ++t) expectNear(faceNormal(s.meshes[0], t), {0, 1, 0}, 1e-6f);
}

// Some exporters write <unit meter> with their locale's decimal comma: read
// as a point with one warning, as Assimp and Blender read it.
TEST(ColladaTransforms, UnitWithADecimalCommaIsReadWithAWarning) {
    TempDir dir;
    Doc d;
    d.unitMeter = "0,01";
    std::vector<std::string> warnings;
    const scene::Scene s = loadQuiet(dir.write("comma.dae", xml(d)), &warnings);
    expectNear(s.meshes[0].positions[1], {0.01f, 0, 0}, 1e-9f);
    EXPECT_TRUE(anyContains(warnings, "<unit meter=\"0,01\"> has a decimal comma; read as 0.01"));
    d.unitMeter = "0,0,1";  // not a number in either form
    EXPECT_THROW(loadQuiet(dir.write("bad.dae", xml(d))), InputError);
}

// Scotty3D's glass <roughness> (which Scotty3D itself never used) is glTF's
// perceptual roughness: 0 keeps the smooth glass, more makes rough glass, a
// value outside [0, 1] is an error.
TEST(ColladaMaterials, GlassRoughnessMakesRoughGlass) {
    TempDir dir;
    auto glassWithRoughness = [](const std::string& roughness) {
        Doc d;
        d.extraEffects =
            effect("glass", "1 1 1",
                   "<glass><ior>1.45</ior><roughness>" + roughness + "</roughness></glass>");
        d.extraMaterials = material("glass");
        d.extraNodes = "<node id=\"Glass\" name=\"Glass\"><instance_geometry url=\"#tri\">" +
                       bind("glass") + "</instance_geometry></node>";
        return xml(d);
    };
    auto glassOf = [](const scene::Scene& s) {
        for (const scene::Material& m : s.materials)
            if (m.name == "glass") return m;
        ADD_FAILURE() << "no material 'glass'";
        return scene::Material{};
    };
    const scene::Material smooth =
        glassOf(loadQuiet(dir.write("smooth.dae", glassWithRoughness("0"))));
    EXPECT_EQ(smooth.kind, scene::MaterialKind::Dielectric);
    const scene::Material rough =
        glassOf(loadQuiet(dir.write("rough.dae", glassWithRoughness("0.3"))));
    EXPECT_EQ(rough.kind, scene::MaterialKind::RoughDielectric);
    EXPECT_FLOAT_EQ(rough.roughness, 0.3f);
    EXPECT_FLOAT_EQ(rough.ior, 1.45f);
    EXPECT_THROW(loadQuiet(dir.write("bad.dae", glassWithRoughness("1.5"))), InputError);
}

// ---------------------------------------------------------------------------
// Bad input: one InputError, one line, naming the file
// ---------------------------------------------------------------------------

void expectInputError(const fs::path& path, const std::string& fragment) {
    try {
        scene::loadScene(path);
        ADD_FAILURE() << "no InputError for " << path;
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(fragment), std::string::npos) << message;
    }
}

TEST(ColladaBadInput, MissingFile) {
    TempDir dir;
    expectInputError(dir.path() / "absent.dae", "no such file");
}

TEST(ColladaBadInput, Directory) {
    TempDir dir;
    fs::create_directories(dir.path() / "folder.dae");
    expectInputError(dir.path() / "folder.dae", "directory");
}

TEST(ColladaBadInput, EmptyFile) {
    TempDir dir;
    expectInputError(dir.write("empty.dae", ""), "empty");
}

TEST(ColladaBadInput, TruncatedXml) {
    TempDir dir;
    const std::string text = xml(Doc{});
    expectInputError(dir.write("truncated.dae", text.substr(0, text.size() / 2)), "XML");
}

TEST(ColladaBadInput, NotCollada) {
    TempDir dir;
    expectInputError(dir.write("other.dae", "<?xml version=\"1.0\"?><svg/>"), "not a COLLADA");
}

TEST(ColladaBadInput, MissingReferencedGeometryId) {
    TempDir dir;
    Doc d;
    d.geometryUrl = "#no-such-geometry";
    expectInputError(dir.write("missing-id.dae", xml(d)), "no-such-geometry");
}

TEST(ColladaBadInput, IndexOutOfRange) {
    TempDir dir;
    Doc d;
    d.p = "0 1 3";  // three positions: 3 is past the end
    expectInputError(dir.write("index.dae", xml(d)), "out of range");
}

TEST(ColladaBadInput, IndicesShorterThanVcount) {
    TempDir dir;
    Doc d;
    d.vcount = "3 3";
    d.p = "0 1 2 0";
    expectInputError(dir.write("short.dae", xml(d)), "<p>");
}

TEST(ColladaBadInput, NanPosition) {
    TempDir dir;
    Doc d;
    d.positions = "0 0 0  nan 0 0  0 1 0";
    expectInputError(dir.write("nan.dae", xml(d)), "not finite");
}

TEST(ColladaBadInput, InfinitePosition) {
    TempDir dir;
    Doc d;
    d.positions = "0 0 0  1e999 0 0  0 1 0";
    expectInputError(dir.write("inf.dae", xml(d)), "not finite");
}

// Scotty3D renders a scene whatever its camera's optics say (it frames the
// scene from its bounds), so vkpath does too: a warning and a 50 degree
// hFov, the camera's direction kept. Likewise a camera that cannot be found.
TEST(ColladaLeniency, MalformedCameraIsAWarningAndScotty3dsFieldOfView) {
    TempDir dir;
    for (const std::string xfov : {"0", "abc", "200"}) {
        Doc d;
        d.xfov = xfov;
        std::vector<std::string> warnings;
        const scene::Scene s = loadQuiet(dir.write("fov.dae", xml(d)), &warnings);
        EXPECT_EQ(s.camera.xfovDegrees, 50.0f) << xfov;
        EXPECT_TRUE(anyContains(warnings, "xfov")) << xfov;
        EXPECT_TRUE(anyContains(warnings, "Scotty3D's 50 degree field of view")) << xfov;
    }
    Doc d;
    std::string text = xml(d);
    text.replace(text.find("<instance_camera url=\"#cam\"/>"),
                 std::strlen("<instance_camera url=\"#cam\"/>"),
                 "<instance_camera url=\"#nowhere\"/>");
    std::vector<std::string> warnings;
    const scene::Scene s = loadQuiet(dir.write("nocam.dae", text), &warnings);
    EXPECT_TRUE(anyContains(warnings, "nowhere")) << (warnings.empty() ? "" : warnings[0]);
    EXPECT_TRUE(anyContains(warnings, "no camera"));
    EXPECT_EQ(s.triangleCount(), 1u);
}

// Scotty3D keeps only a camera's direction (SOURCE.md), and reads a node's
// <matrix> as whatever numbers it holds: a camera node whose transform is
// malformed (15 numbers, a word, a degenerate <lookat>) is a warning, and the
// camera is placed by Scotty3D's rule as when there is none (from +Z). A node
// that holds geometry with such a transform is still refused: nothing says
// where its triangles are.
TEST(ColladaLeniency, MalformedCameraTransformIsAWarningAndScotty3dsPlacement) {
    TempDir dir;
    const std::string cameraMatrix = "<matrix>1 0 0 0 0 1 0 0 0 0 1 5 0 0 0 1</matrix>";
    for (const std::string bad : {"<matrix>1 0 0 0 0 1 0 0 0 0 1 5 0 0 0</matrix>",
                                  "<matrix>1 0 0 0 0 1 0 0 0 0 1 five 0 0 0 1</matrix>",
                                  "<lookat>0 0 0 0 0 0 0 1 0</lookat>"}) {
        SCOPED_TRACE(bad);
        std::string text = xml(Doc{});
        text.replace(text.find(cameraMatrix), cameraMatrix.size(), bad);
        std::vector<std::string> warnings;
        const scene::Scene s = loadQuiet(dir.write("camera.dae", text), &warnings);
        EXPECT_TRUE(anyContains(warnings, "node 'Camera'"));
        EXPECT_TRUE(anyContains(warnings, "the camera is placed by Scotty3D's rule from +Z"));
        EXPECT_EQ(s.camera.name, "Camera");
        EXPECT_EQ(s.camera.xfovDegrees, 50.0f) << "the optics are still read";
        EXPECT_FLOAT_EQ(s.camera.position.x, s.camera.target.x);
        EXPECT_FLOAT_EQ(s.camera.position.y, s.camera.target.y);
        EXPECT_GT(s.camera.position.z, s.camera.target.z);
    }
    Doc d;
    d.nodeMatrix = "1 0 0 0  0 1 0 0  0 0 1 0  0 0 0";
    expectInputError(dir.write("geometry.dae", xml(d)), "has 15 numbers, needs 16");
}

TEST(ColladaBadInput, NoGeometry) {
    TempDir dir;
    Doc d;
    d.geometryNode = false;
    expectInputError(dir.write("nothing.dae", xml(d)), "no geometry");
}

TEST(ColladaBadInput, NonPositiveSphereRadius) {
    TempDir dir;
    Doc d;
    d.extraGeometries = R"(<geometry id="ball" name="ball"><extra><technique profile="CMU462">
        <sphere><radius>-1</radius></sphere></technique></extra></geometry>)";
    d.extraNodes = R"(<node id="Ball" name="Ball"><instance_geometry url="#ball"/></node>)";
    expectInputError(dir.write("radius.dae", xml(d)), "radius");
}

TEST(ColladaBadInput, CyclicNodeInstancing) {
    TempDir dir;
    Doc d;
    d.extraNodes = R"(<node id="Loop" name="Loop"><instance_node url="#Loop"/></node>)";
    expectInputError(dir.write("cycle.dae", xml(d)), "deeper");
}

TEST(ColladaBadInput, UnknownExtension) {
    TempDir dir;
    expectInputError(dir.write("scene.obj", "o x\n"), "unknown scene format '.obj'");
    // Upper case is the same format: dispatched to the COLLADA importer.
    EXPECT_NO_THROW(loadQuiet(dir.write("SCENE.DAE", xml(Doc{}))));
    EXPECT_NO_THROW(scene::loadScene(dir.path() / "SCENE.DAE"));
}

}  // namespace
