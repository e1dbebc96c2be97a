// `vkpath scene-info` as a user meets it: the summary of a shared scene, its
// JSON form, and bad input as exit code 2 with one line naming the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/run_vkpath.h"
#include "support/test_context.h"

namespace {

using vkpath::test::lineCount;
using vkpath::test::runVkpath;
namespace fs = std::filesystem;

std::string quoted(const fs::path& path) {
    // Built in steps: GCC 12 warns (-Wrestrict, falsely) on "'" + s + "'".
    std::string s(1, '\'');
    s += path.string();
    s += '\'';
    return s;
}

// The value after `key` on the line that starts with it, or "" if none.
std::string field(const std::string& text, const std::string& key) {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind(key + " ", 0) == 0) {
            const size_t start = line.find_first_not_of(' ', key.size());
            return start == std::string::npos ? "" : line.substr(start);
        }
    return "";
}

TEST(SceneInfo, CBspheresSummary) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const auto r = runVkpath("scene-info " + quoted(vkpath::test::sharedScene("CBspheres.dae")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // Six walls, ceiling and lamp of two triangles each (the file's vcounts).
    EXPECT_EQ(field(r.out, "triangles"), "12") << r.out;
    EXPECT_EQ(field(r.out, "spheres"), "2") << r.out;
    EXPECT_EQ(field(r.out, "emitters"), "1 (meshes 1, spheres 0; emissive triangles 2)") << r.out;
    EXPECT_NE(field(r.out, "features").find("mirror glass"), std::string::npos) << r.out;
    EXPECT_FALSE(field(r.out, "camera").empty());
    EXPECT_FALSE(field(r.out, "bounds").empty());
    EXPECT_NE(field(r.out, "kernels").find("mirror glass emissive-surfaces"), std::string::npos)
        << r.out;
    EXPECT_NE(field(r.out, "memory").find("megakernel 12 B"), std::string::npos) << r.out;
    // The lamp is described twice; the decision is reported, once, on stderr.
    const std::string prefix =
        "vkpath: warning: " + vkpath::test::sharedScene("CBspheres.dae").string() + ": area light";
    EXPECT_NE(r.err.find(prefix), std::string::npos) << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
}

// A textured glTF made by others (Debian's assimp-testmodels): its one image
// (211 x 211, CesiumLogoFlat.png) decoded, and kernels with the texture code.
TEST(SceneInfo, TexturedSceneCountsItsTextures) {
    const std::filesystem::path file =
        "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    if (!std::filesystem::exists(file))
        GTEST_SKIP() << "assimp-testmodels is not installed (tools/install-deps)";
    const auto r = runVkpath("scene-info " + quoted(file));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(field(r.out, "textures"), "1 (1 images, 44521 texels)") << r.out;
    EXPECT_NE(field(r.out, "kernels").find("textures"), std::string::npos) << r.out;
    const auto flat =
        runVkpath("scene-info " + quoted(vkpath::test::sourcePath("assets/cornell_box.gltf")));
    EXPECT_EQ(field(flat.out, "textures"), "0 (0 images, 0 texels)") << flat.out;
    EXPECT_EQ(field(flat.out, "kernels").find("textures"), std::string::npos) << flat.out;
}

TEST(SceneInfo, JsonMatchesTheText) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const auto r =
        runVkpath("scene-info --json " + quoted(vkpath::test::sharedScene("CBspheres.dae")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto json = nlohmann::json::parse(r.out);
    EXPECT_EQ(json["triangles"].get<size_t>(), 12u);
    EXPECT_EQ(json["spheres"].get<size_t>(), 2u);
    EXPECT_EQ(json["materials"]["mirror"].get<size_t>(), 1u);
    EXPECT_EQ(json["materials"]["glass"].get<size_t>(), 1u);
    EXPECT_EQ(json["emitters"]["meshes"].get<size_t>(), 1u);
    EXPECT_EQ(json["emitters"]["triangles"].get<size_t>(), 2u);
    EXPECT_EQ(json["lights"]["point"].get<size_t>(), 0u);
    EXPECT_TRUE(json["features"]["glass"].get<bool>());
    EXPECT_FALSE(json["features"]["pointLights"].get<bool>());
    EXPECT_NEAR(json["camera"]["xfovDegrees"].get<double>(), 49.13434, 1e-4);
    EXPECT_NEAR(json["bounds"]["max"][1].get<double>(), 1.5, 1e-6);
    // The kernels a default render builds, and what they take on the device:
    // the same text as `render` prints.
    EXPECT_EQ(json["kernelFeatures"].get<std::string>(),
              "triangles spheres diffuse mirror glass emissive-surfaces sobol-sampler "
              "light-samples roulette "
              "sphere-guiding");
    EXPECT_EQ(json["deviceBytes"]["perPathMegakernel"].get<uint64_t>(), 12u);
    EXPECT_GT(json["deviceBytes"]["perPathWavefront"].get<uint64_t>(), 100u);
    EXPECT_GT(json["deviceBytes"]["scene"].get<uint64_t>(), 14u * 48u)
        << "at least the BVH's 14 primitives";
}

TEST(SceneInfo, MissingFileIsExitTwoAndOneLine) {
    const std::string path = "/nonexistent-vkpath-dir/absent.dae";
    const auto r = runVkpath("scene-info " + path);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(path), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

// Bad documents, each wrong in one way; the loader's own tests check the
// message, these check what the user sees.
struct BadCase {
    const char* name;
    std::string text;
};

std::string triangleScene(const std::string& positions, const std::string& p,
                          const std::string& url, const std::string& xfov, bool withGeometry) {
    std::string s = R"(<?xml version="1.0"?>
<COLLADA version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset>
<library_cameras><camera id="cam"><optics><technique_common><perspective><xfov>)" +
                    xfov +
                    R"(</xfov></perspective></technique_common></optics></camera></library_cameras>
<library_geometries><geometry id="tri"><mesh>
  <source id="pos"><float_array id="pos-array">)" +
                    positions + R"(</float_array>
    <technique_common><accessor source="#pos-array" count="3" stride="3"/></technique_common>
  </source>
  <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
  <triangles count="1"><input semantic="VERTEX" source="#verts" offset="0"/><p>)" +
                    p +
                    R"(</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s">
  <node id="cam-node"><matrix>1 0 0 0 0 1 0 0 0 0 1 5 0 0 0 1</matrix>
    <instance_camera url="#cam"/></node>)";
    if (withGeometry) s += "<node id=\"tri-node\"><instance_geometry url=\"" + url + "\"/></node>";
    return s + R"(</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>
)";
}

std::vector<BadCase> badCases() {
    const std::string good = "0 0 0 1 0 0 0 1 0";
    const std::string valid = triangleScene(good, "0 1 2", "#tri", "50", true);
    return {
        {"empty", ""},
        {"truncated", valid.substr(0, valid.size() / 2)},
        {"missing_geometry_id", triangleScene(good, "0 1 2", "#nope", "50", true)},
        {"index_out_of_range", triangleScene(good, "0 1 7", "#tri", "50", true)},
        {"nan_position", triangleScene("0 0 0 nan 0 0 0 1 0", "0 1 2", "#tri", "50", true)},
        {"no_geometry", triangleScene(good, "0 1 2", "#tri", "50", false)},
    };
}

class SceneInfoBadInput : public testing::TestWithParam<BadCase> {};

TEST_P(SceneInfoBadInput, ExitTwoOneLineNamingTheFile) {
    const fs::path dir = fs::temp_directory_path() /
                         ("vkpath-scene-info-" + std::to_string(getpid()) + "-" + GetParam().name);
    fs::create_directories(dir);
    const fs::path file = dir / (std::string(GetParam().name) + ".dae");
    std::ofstream(file, std::ios::binary) << GetParam().text;
    const auto r = runVkpath("scene-info " + quoted(file));
    fs::remove_all(dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(file.string() + ": "), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;  // nothing printed half-way
}

INSTANTIATE_TEST_SUITE_P(Cases, SceneInfoBadInput, testing::ValuesIn(badCases()),
                         [](const testing::TestParamInfo<BadCase>& param) {
                             return std::string(param.param.name);
                         });

}  // namespace
