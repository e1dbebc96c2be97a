// `vkpath export-mitsuba` as a user runs it: the written Mitsuba 3 scene
// parses, holds one shape per mesh and sphere of the loaded scene with the
// right BSDFs and emitters, the sensor vkpath renders with, the max depth
// shifted to Mitsuba's meaning, and PLY files whose headers and data are the
// scene's own. Bad input: one line, exit code 2, nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <pugixml.hpp>
#include <sstream>
#include <string>

#include "image/image.h"
#include "scene/camera.h"
#include "scene/load.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"
#include "support/vdb_grid.h"
#include "wavefront/render_types.h"

namespace {

using vkpath::test::lineCount;
using vkpath::test::runVkpath;
namespace fs = std::filesystem;
namespace scene = vkpath::scene;

std::string quoted(const fs::path& path) {
    std::string s(1, '\'');
    s += path.string();
    s += '\'';
    return s;
}

// The `value` attribute of the child <tag name="name">.
std::string param(pugi::xml_node node, const char* tag, const char* name) {
    return node.find_child_by_attribute(tag, "name", name).attribute("value").as_string();
}

// Top-level BSDFs by id, each as its type ("twosided/diffuse" for a wrapped one).
std::map<std::string, std::string> bsdfTypes(pugi::xml_node root) {
    std::map<std::string, std::string> types;
    for (pugi::xml_node bsdf : root.children("bsdf")) {
        std::string type = bsdf.attribute("type").as_string();
        if (type == "twosided")
            type += std::string("/") + bsdf.child("bsdf").attribute("type").as_string();
        types[bsdf.attribute("id").as_string()] = type;
    }
    return types;
}

std::string expectedBsdf(const scene::Material& m) {
    switch (m.kind) {
        case scene::MaterialKind::Diffuse:
            return "twosided/diffuse";
        case scene::MaterialKind::Mirror:
            return "twosided/conductor";
        case scene::MaterialKind::Dielectric:
            return "dielectric";
        case scene::MaterialKind::Conductor:
            return m.roughness * m.roughness < 1e-3f ? "twosided/conductor"
                                                     : "twosided/roughconductor";
        case scene::MaterialKind::RoughDielectric:
            return m.roughness * m.roughness < 1e-3f ? "dielectric" : "roughdielectric";
        case scene::MaterialKind::MetallicRoughness:
            return "twosided/principled";
    }
    return "";
}

// Reads a PLY written by the exporter and checks it against `mesh`: the
// header's counts and properties, then every position and index.
void expectPlyIsMesh(const fs::path& path, const scene::Mesh& mesh) {
    std::ifstream in(path, std::ios::binary);
    ASSERT_TRUE(in) << path;
    std::string header, line;
    while (std::getline(in, line)) {
        header += line + "\n";
        if (line == "end_header") break;
    }
    const bool normals = !mesh.normals.empty();
    std::string expected =
        "ply\nformat binary_little_endian 1.0\ncomment vkpath export-mitsuba\nelement vertex " +
        std::to_string(mesh.positions.size()) +
        "\nproperty float x\nproperty float y\nproperty float z\n";
    if (normals) expected += "property float nx\nproperty float ny\nproperty float nz\n";
    expected += "element face " + std::to_string(mesh.triangles.size()) +
                "\nproperty list uchar int vertex_indices\nend_header\n";
    ASSERT_EQ(header, expected) << path;

    const size_t stride = normals ? 6 : 3;
    std::vector<float> vertices(mesh.positions.size() * stride);
    in.read(reinterpret_cast<char*>(vertices.data()),
            std::streamsize(vertices.size() * sizeof(float)));
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        ASSERT_EQ(std::memcmp(&vertices[i * stride], &mesh.positions[i], 12), 0)
            << path << " vertex " << i;
        if (normals) {
            ASSERT_EQ(std::memcmp(&vertices[i * stride + 3], &mesh.normals[i], 12), 0) << path;
        }
    }
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        unsigned char count = 0;
        int32_t idx[3];
        in.read(reinterpret_cast<char*>(&count), 1);
        in.read(reinterpret_cast<char*>(idx), sizeof(idx));
        ASSERT_EQ(count, 3);
        ASSERT_EQ(glm::uvec3(idx[0], idx[1], idx[2]), mesh.triangles[t]) << path << " face " << t;
    }
    in.peek();
    EXPECT_TRUE(in.eof()) << path << ": bytes after the last face";
}

// Exports `scenePath` with `flags`, then checks scene.xml against the scene
// vkpath loads: shapes, BSDFs, emitters, sensor, integrator, PLY files.
pugi::xml_document exportAndCheck(const fs::path& scenePath, const std::string& flags,
                                  const fs::path& out, uint32_t width, uint32_t height,
                                  uint32_t maxDepth) {
    const auto r =
        runVkpath("export-mitsuba " + quoted(scenePath) + " " + quoted(out) + " " + flags);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out, (out / "scene.xml").string() + "\n");

    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_file((out / "scene.xml").c_str());
    EXPECT_TRUE(parsed) << parsed.description();
    const pugi::xml_node root = doc.child("scene");
    EXPECT_EQ(std::string(root.attribute("version").as_string()).substr(0, 2), "3.");

    const scene::Scene s = scene::loadScene(scenePath);
    const auto bsdfs = bsdfTypes(root);
    EXPECT_EQ(bsdfs.size(), s.materials.size());
    for (size_t i = 0; i < s.materials.size(); ++i)
        EXPECT_EQ(bsdfs.at("mat" + std::to_string(i)), expectedBsdf(s.materials[i]))
            << s.materials[i].name;

    // Shapes in scene order: the meshes (as PLY), then the spheres.
    size_t meshIndex = 0, sphereIndex = 0, areaEmitters = 0, expectedAreaEmitters = 0;
    for (pugi::xml_node shape : root.children("shape")) {
        const std::string type = shape.attribute("type").as_string();
        const uint32_t material =
            type == "ply" ? s.meshes.at(meshIndex).material : s.spheres.at(sphereIndex).material;
        EXPECT_EQ(std::string(shape.child("ref").attribute("id").as_string()),
                  "mat" + std::to_string(material));
        areaEmitters += bool(shape.find_child_by_attribute("emitter", "type", "area"));
        expectedAreaEmitters += s.materials[material].emissive();
        if (type == "ply") {
            EXPECT_EQ(param(shape, "boolean", "face_normals"),
                      s.meshes[meshIndex].normals.empty() ? "true" : "false");
            expectPlyIsMesh(out / param(shape, "string", "filename"), s.meshes[meshIndex++]);
        } else {
            EXPECT_EQ(type, "sphere");
            const scene::Sphere& sphere = s.spheres.at(sphereIndex++);
            EXPECT_FLOAT_EQ(std::stof(param(shape, "float", "radius")), sphere.radius);
            EXPECT_FLOAT_EQ(
                shape.find_child_by_attribute("point", "name", "center").attribute("y").as_float(),
                sphere.center.y);
        }
    }
    EXPECT_EQ(meshIndex, s.meshes.size());
    EXPECT_EQ(sphereIndex, s.spheres.size());
    EXPECT_EQ(areaEmitters, expectedAreaEmitters);
    EXPECT_GT(areaEmitters, 0u);

    const pugi::xml_node integrator = root.child("integrator");
    EXPECT_EQ(std::string(integrator.attribute("type").as_string()), "path");
    EXPECT_EQ(param(integrator, "integer", "max_depth"), std::to_string(maxDepth + 1));
    EXPECT_EQ(param(integrator, "integer", "rr_depth"),
              std::to_string(vkpath::wavefront::RenderSettings{}.rouletteDepth));

    const pugi::xml_node sensor = root.child("sensor");
    EXPECT_EQ(param(sensor, "string", "fov_axis"), "x");
    const float tanX = glm::length(scene::makeGpuCamera(s.camera, width, height).right);
    EXPECT_NEAR(std::stof(param(sensor, "float", "fov")), glm::degrees(2 * std::atan(tanX)), 1e-4);
    const pugi::xml_node film = sensor.child("film");
    EXPECT_EQ(param(film, "integer", "width"), std::to_string(width));
    EXPECT_EQ(param(film, "integer", "height"), std::to_string(height));
    EXPECT_EQ(std::string(film.child("rfilter").attribute("type").as_string()), "box");
    return doc;
}

TEST(ExportMitsuba, CBspheres) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const vkpath::test::TempDir dir;
    const fs::path scenePath = vkpath::test::sharedScene("CBspheres.dae");
    const pugi::xml_document doc =
        exportAndCheck(scenePath, "-d 80x60 -m 5 -s 7", dir / "cb", 80, 60, 5);
    const pugi::xml_node root = doc.child("scene");
    EXPECT_EQ(param(root.child("sensor").child("sampler"), "integer", "sample_count"), "7");
    // Floor, ceiling, three walls and the lamp; a mirror and a glass sphere; no environment.
    EXPECT_EQ(std::distance(root.children("shape").begin(), root.children("shape").end()), 6 + 2);
    const pugi::xml_node glass = root.find_child_by_attribute("bsdf", "type", "dielectric");
    EXPECT_EQ(param(glass, "float", "ext_ior"), "1");
    EXPECT_FALSE(root.child("emitter"));
}

TEST(ExportMitsuba, CornellBoxUnderTheSky) {
    const vkpath::test::TempDir dir;
    const fs::path source = VKPATH_SOURCE_DIR;
    const pugi::xml_document doc =
        exportAndCheck(source / "assets/cornell_box.gltf",
                       "-d 64x48 -m 0 -e " + quoted(source / "assets/sky.hdr") +
                           " --env-strength 2 --env-rotate 30",
                       dir / "cb", 64, 48, 0);
    const pugi::xml_node env =
        doc.child("scene").find_child_by_attribute("emitter", "type", "envmap");
    ASSERT_TRUE(env);
    EXPECT_EQ(param(env, "float", "scale"), "2");
    const pugi::xml_node rotate = env.child("transform").child("rotate");
    EXPECT_EQ(std::string(rotate.attribute("y").as_string()), "1");
    EXPECT_EQ(std::string(rotate.attribute("angle").as_string()), "30");
    // The texels vkpath renders with.
    const vkpath::image::Image map =
        vkpath::image::readImage(dir / "cb" / param(env, "string", "filename"));
    EXPECT_EQ(map.width, 2048u);
    EXPECT_EQ(map.height, 1024u);
}

// An instanced mesh is written once, as a shape group of its primitives'
// PLYs, and each placement as an instance shape with its matrix, row by row.
TEST(ExportMitsuba, InstancedMeshesAreShapeGroupsPlacedByInstances) {
    const vkpath::test::TempDir dir;
    const fs::path scenePath = vkpath::test::sourcePath("assets/instances.gltf");
    const auto r = runVkpath("export-mitsuba " + quoted(scenePath) + " " + quoted(dir / "i") +
                             " --instancing on");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file((dir / "i" / "scene.xml").c_str()));
    scene::LoadOptions on;
    on.instancing = scene::Instancing::On;
    const scene::Scene s = scene::loadScene(scenePath, on);
    ASSERT_EQ(s.instances.size(), 30u);
    std::vector<pugi::xml_node> groups, instances;
    for (pugi::xml_node shape : doc.child("scene").children("shape")) {
        const std::string type = shape.attribute("type").as_string();
        if (type == "shapegroup") groups.push_back(shape);
        if (type == "instance") instances.push_back(shape);
    }
    ASSERT_EQ(groups.size(), 1u);
    EXPECT_EQ(std::distance(groups[0].children("shape").begin(), groups[0].children("shape").end()),
              2);
    for (pugi::xml_node ply : groups[0].children("shape"))
        EXPECT_TRUE(fs::exists(dir / "i" / param(ply, "string", "filename")));
    ASSERT_EQ(instances.size(), s.instances.size());
    for (size_t i = 0; i < instances.size(); ++i) {
        EXPECT_EQ(std::string(instances[i].child("ref").attribute("id").as_string()),
                  groups[0].attribute("id").as_string());
        std::istringstream values(
            instances[i].child("transform").child("matrix").attribute("value").as_string());
        for (int row = 0; row < 4; ++row)
            for (int column = 0; column < 4; ++column) {
                float v = NAN;
                values >> v;
                EXPECT_FLOAT_EQ(v, float(s.instances[i].objectToWorld[column][row]));
            }
    }
}

TEST(ExportMitsuba, ConstantEnvironment) {
    const vkpath::test::TempDir dir;
    const fs::path source = VKPATH_SOURCE_DIR;
    exportAndCheck(source / "assets/cornell_box.gltf",
                   "-d 32x32 --env-color 0.5,1,2 --env-strength 2", dir / "cb", 32, 32, 8);
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file((dir / "cb/scene.xml").c_str()));
    const pugi::xml_node env =
        doc.child("scene").find_child_by_attribute("emitter", "type", "constant");
    EXPECT_EQ(param(env, "rgb", "radiance"), "1, 2, 4");
}

// Normal maps are not exported: the export says so once, counting the
// meshes, and still writes the scene.
TEST(ExportMitsuba, NormalMapsAreWarnedAbout) {
    const vkpath::test::TempDir dir;
    const fs::path source = VKPATH_SOURCE_DIR;
    const auto r = runVkpath("export-mitsuba " + quoted(source / "assets/normal_maps.gltf") + " " +
                             quoted(dir / "nm") + " -d 32x24");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(
        r.err.find(
            "normal maps are not exported: Mitsuba shades those meshes with their vertex normals "
            "(3 meshes)"),
        std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::exists(dir / "nm/scene.xml"));
}

// Textures and alpha are not exported either: Debian's TextureTransformTest
// (base-colour textures) says so, counting the materials.
TEST(ExportMitsuba, TexturesAreWarnedAbout) {
    const fs::path model =
        "/usr/share/assimp/models/glTF2/textureTransform/TextureTransformTest.gltf";
    if (!fs::exists(model)) GTEST_SKIP() << model << " absent (Debian's assimp-testmodels)";
    const vkpath::test::TempDir dir;
    const auto r = runVkpath("export-mitsuba " + quoted(model) + " " + quoted(dir / "tt") +
                             " -d 32x24 --env-color 1,1,1");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("base-colour, emissive and metallic-roughness textures are not exported"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::exists(dir / "tt/scene.xml"));
}

// glTF's material extensions: the clear coats, sheens, diffuse transmission
// and thin films are left out and said so (14 materials), thin walls become
// Mitsuba's thindielectric (2 materials, warned: Mitsuba's is smooth and adds
// the interreflections inside the wall).
TEST(ExportMitsuba, MaterialExtensionsAreWarnedAbout) {
    const vkpath::test::TempDir dir;
    const fs::path source = VKPATH_SOURCE_DIR;
    const auto r =
        runVkpath("export-mitsuba " + quoted(source / "assets/material_extensions.gltf") + " " +
                  quoted(dir / "me") + " -d 32x24");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("clear coats, sheens, diffuse transmission and thin films"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("those materials are written without them (14 materials)"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("written as Mitsuba's thindielectric"), std::string::npos) << r.err;
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file((dir / "me/scene.xml").c_str()));
    size_t thin = 0;
    for (const auto& [id, type] : bsdfTypes(doc.child("scene"))) thin += type == "thindielectric";
    EXPECT_EQ(thin, 2u);
}

TEST(ExportMitsuba, BadInputIsOneLineAndNothingWritten) {
    const vkpath::test::TempDir dir;
    const fs::path missing = dir / "missing.gltf";
    auto r = runVkpath("export-mitsuba " + quoted(missing) + " " + quoted(dir / "out"));
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(missing.string()), std::string::npos) << r.err;

    r = runVkpath("export-mitsuba " + quoted(vkpath::test::sourcePath("assets/cornell_box.gltf")) +
                  " " + quoted(dir / "out") + " -d 0x10");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace

// The fog (render --fog-*) and a scattering glass inside: Mitsuba's volpath,
// a homogeneous medium per medium (sigma_t, albedo, an hg phase function),
// the camera in the fog, every shape's exterior the fog and the glass
// sphere's interior its own medium.
TEST(ExportMitsuba, FogAndScatteringGlassAreVolpathMedia) {
    const vkpath::test::TempDir dir;
    const fs::path out = dir / "foggy";
    const auto r = runVkpath(
        "export-mitsuba " + quoted(vkpath::test::sourcePath("assets/cornell_box.gltf")) + " " +
        quoted(out) + " -d 16x16 --fog-density 0.5 --fog-albedo 0.8 --fog-anisotropy 0.25");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file((out / "scene.xml").c_str()));
    const pugi::xml_node root = doc.child("scene");
    EXPECT_EQ(std::string(root.child("integrator").attribute("type").as_string()), "volpath");
    const pugi::xml_node fog = root.find_child_by_attribute("medium", "id", "fog");
    ASSERT_TRUE(fog);
    EXPECT_EQ(std::string(fog.attribute("type").as_string()), "homogeneous");
    EXPECT_EQ(
        std::string(
            fog.find_child_by_attribute("rgb", "name", "sigma_t").attribute("value").as_string()),
        "1, 1, 1");
    EXPECT_EQ(param(fog, "float", "scale"), "0.5");
    EXPECT_NEAR(
        std::stof(
            fog.find_child_by_attribute("rgb", "name", "albedo").attribute("value").as_string()),
        0.8f, 1e-6f);
    EXPECT_EQ(param(fog.child("phase"), "float", "g"), "0.25");
    EXPECT_EQ(std::string(root.child("sensor").child("ref").attribute("id").as_string()), "fog");
    size_t shapes = 0;
    for (pugi::xml_node shape : root.children("shape")) {
        ++shapes;
        EXPECT_EQ(std::string(shape.find_child_by_attribute("ref", "name", "exterior")
                                  .attribute("id")
                                  .as_string()),
                  "fog");
    }
    EXPECT_GT(shapes, 0u);
    // The medium is declared before the sensor that refers to it.
    EXPECT_EQ(std::string(root.child("medium").next_sibling("sensor").name()), "sensor");
}

// The grid medium (render --volume): Mitsuba's heterogeneous medium over a
// gridvolume file (volume.vol: "VOL" version 3, float32, the resolution and
// the voxels) inside a null-BSDF cube around the voxels' cells.
TEST(ExportMitsuba, GridMediumIsAHeterogeneousMediumInACube) {
    const vkpath::test::TempDir dir;
    const auto grid = vkpath::test::writeGrid(dir / "smoke.vdb", 4, 0.5, {0, 0, 0},
                                              [](int i, int, int) { return float(i + 1); });
    const fs::path out = dir / "smoky";
    const auto r =
        runVkpath("export-mitsuba " + quoted(vkpath::test::sourcePath("assets/cornell_box.gltf")) +
                  " " + quoted(out) + " -d 16x16 --volume " + quoted(grid) +
                  " --volume-density 3 --volume-albedo 0.5");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file((out / "scene.xml").c_str()));
    const pugi::xml_node root = doc.child("scene");
    EXPECT_EQ(std::string(root.child("integrator").attribute("type").as_string()), "volpath");
    const pugi::xml_node medium = root.find_child_by_attribute("medium", "id", "volume");
    ASSERT_TRUE(medium);
    EXPECT_EQ(std::string(medium.attribute("type").as_string()), "heterogeneous");
    EXPECT_EQ(param(medium, "float", "scale"), "3");
    const pugi::xml_node cube = root.find_child_by_attribute("shape", "type", "cube");
    ASSERT_TRUE(cube);
    EXPECT_EQ(std::string(cube.child("bsdf").attribute("type").as_string()), "null");
    EXPECT_EQ(
        std::string(
            cube.find_child_by_attribute("ref", "name", "interior").attribute("id").as_string()),
        "volume");
    std::ifstream vol(out / "volume.vol", std::ios::binary);
    char header[4] = {};
    vol.read(header, 4);
    EXPECT_EQ(std::string(header, 3), "VOL");
    EXPECT_EQ(header[3], 3);
    int32_t fields[5];
    vol.read(reinterpret_cast<char*>(fields), sizeof(fields));
    EXPECT_EQ(fields[0], 1);  // float32
    EXPECT_EQ(fields[1], 6);  // 4 voxels and a voxel of 0 either side
    EXPECT_EQ(fields[4], 1);  // one channel
    vol.seekg(0, std::ios::end);
    EXPECT_EQ(int(vol.tellg()), 48 + 6 * 6 * 6 * 4);
}
