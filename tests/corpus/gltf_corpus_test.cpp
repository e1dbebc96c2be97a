// The glTF 2.0 files of Debian's assimp-testmodels package (made by others,
// good, broken and odd; tools/install-deps installs it, and the tests read
// them where it puts them, never a copy in the tree), each rendered as a user
// would: `vkpath render FILE` at 1 spp on a 32 x 24 film. Every file either
// renders (exit 0, a complete EXR) or is refused (exit 2, exactly one line
// that names the file, nothing written); never a crash, a hang, a Vulkan
// validation message or a partial file. One test per file, so a failure names
// it. The cost is start-up, not pixels (docs/ACCURACY.md gives the times).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "image/image.h"
#include "input_error.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;

const fs::path CORPUS = "/usr/share/assimp/models/glTF2";
const char* const ABSENT = "assimp_testmodels_not_installed";

// Seconds one render may take. The slowest file takes 2.2 s with a warm
// pipeline cache and 5.7 s with a cold one on two busy cores; ten times that
// is a hang, not a slow machine.
constexpr int TIMEOUT_SECONDS = 60;
constexpr uint32_t WIDTH = 32, HEIGHT = 24;

// What a file must do beyond "render or be refused cleanly". Valid files that
// issue 13 names (or that are plain core glTF 2.0) must render: refusing them
// is the bug the corpus exists to catch. The broken ones may go either way.
enum class Expect { RenderOrRefuse, Render };

struct Rule {
    Expect expect;
    const char* mustMention;  // a refusal must name this (nullptr: anything)
};

const std::map<std::string, Rule>& rules() {
    static const std::map<std::string, Rule> table = {
        {"2CylinderEngine-glTF-Binary/2CylinderEngine.glb", {Expect::Render, nullptr}},
        {"BoxTexcoords-glTF/boxTexcoords.gltf", {Expect::Render, nullptr}},
        {"BoxTextured-glTF/BoxTextured.gltf", {Expect::Render, nullptr}},
        {"BoxTextured-glTF-Binary/BoxTextured.glb", {Expect::Render, nullptr}},
        {"BoxTextured-glTF-Embedded/BoxTextured.gltf", {Expect::Render, nullptr}},
        // pbrSpecularGlossiness is used, not required: a viewer without it draws the core material.
        {"BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf", {Expect::Render, nullptr}},
        {"cameras/Cameras.gltf", {Expect::Render, nullptr}},
        {"ClearCoat-glTF/ClearCoatTest.gltf", {Expect::Render, nullptr}},
        {"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
         {Expect::Render, nullptr}},
        {"simple_skin/simple_skin.gltf", {Expect::Render, nullptr}},
        {"textureTransform/TextureTransformTest.gltf", {Expect::Render, nullptr}},
        // TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN, not indexed (04-06) and indexed (11-15).
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf",
         {Expect::Render, nullptr}},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf",
         {Expect::Render, nullptr}},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf",
         {Expect::Render, nullptr}},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf",
         {Expect::Render, nullptr}},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf",
         {Expect::Render, nullptr}},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf",
         {Expect::Render, nullptr}},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_14.gltf",
         {Expect::Render, nullptr}},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_15.gltf",
         {Expect::Render, nullptr}},
        // Issue 13: Draco is read, or refused by the extension's name (not "invalid bufferView").
        {"draco/2CylinderEngine.gltf", {Expect::RenderOrRefuse, "KHR_draco_mesh_compression"}},
    };
    return table;
}

std::string lowercase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Every .gltf and .glb under the corpus, relative to it, sorted; the one
// entry ABSENT when the package is not installed.
std::vector<std::string> corpusFiles() {
    std::error_code ec;
    if (!fs::is_directory(CORPUS, ec)) return {ABSENT};
    std::vector<std::string> files;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(CORPUS, ec)) {
        const std::string extension = lowercase(e.path().extension().string());
        if (e.is_regular_file() && (extension == ".gltf" || extension == ".glb"))
            files.push_back(fs::relative(e.path(), CORPUS).string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

// A test name from a relative path: letters and digits kept, the rest '_'.
std::string testName(const testing::TestParamInfo<std::string>& info) {
    std::string name = info.param;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
        names.push_back(e.path().filename().string());
    return names;
}

class GltfCorpus : public testing::TestWithParam<std::string> {};

TEST_P(GltfCorpus, RendersOrIsRefusedWithOneLine) {
    if (GetParam() == ABSENT)
        GTEST_SKIP()
            << CORPUS
            << " is missing: Debian's assimp-testmodels is not installed (tools/install-deps)";
    const fs::path file = CORPUS / GetParam();
    const test::TempDir dir;
    const fs::path exr = dir / "out.exr";
    // --validation: a validation message is exit 1 even outside CTest's environment.
    const test::CommandResult r = test::runVkpath(
        "--validation render '" + file.string() + "' -d " + std::to_string(WIDTH) + "x" +
            std::to_string(HEIGHT) + " -s 1 --env-color 1,1,1 -o '" + exr.string() + "'",
        TIMEOUT_SECONDS);
    ASSERT_FALSE(r.timedOut) << file << ": still running (or killed) after " << TIMEOUT_SECONDS
                             << " s\n"
                             << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << file << ":\n" << r.err;
    ASSERT_TRUE(r.exitCode == 0 || r.exitCode == 2) << file << ": exit code " << r.exitCode << "\n"
                                                    << r.err;

    const auto rule = rules().find(GetParam());
    if (r.exitCode == 2) {
        EXPECT_TRUE(rule == rules().end() || rule->second.expect != Expect::Render)
            << file << " is valid glTF 2.0 and must render, but:\n"
            << r.err;
        EXPECT_EQ(test::lineCount(r.err), 1) << file << ":\n" << r.err;
        EXPECT_EQ(r.err.rfind("vkpath: " + file.string() + ": ", 0), 0u)
            << "the line names the file:\n"
            << r.err;
        if (rule != rules().end() && rule->second.mustMention) {
            EXPECT_NE(r.err.find(rule->second.mustMention), std::string::npos)
                << "the refusal should name " << rule->second.mustMention << ":\n"
                << r.err;
        }
        EXPECT_TRUE(filesIn(dir.path()).empty()) << file << ": refused, but something was written";
        return;
    }
    // Rendered: the EXR and nothing else (no temporary file left beside it).
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"out.exr"}) << file;
    image::Image image;
    try {
        image = image::readImage(exr);
    } catch (const InputError& e) {
        FAIL() << file << ": the EXR cannot be read: " << e.what();
    }
    ASSERT_EQ(image.width, WIDTH);
    ASSERT_EQ(image.height, HEIGHT);
    size_t bad = 0;
    for (const glm::vec3& p : image.pixels)
        for (int c = 0; c < 3; ++c) bad += !(std::isfinite(p[c]) && p[c] >= 0.0f);
    EXPECT_EQ(bad, 0u) << file << ": pixel values that are negative, NaN or infinite";
}

INSTANTIATE_TEST_SUITE_P(AssimpTestModels, GltfCorpus, testing::ValuesIn(corpusFiles()), testName);

// The table above names files that exist: a renamed file would silently lose its rule.
TEST(GltfCorpusRules, NameFilesOfThePackage) {
    if (!fs::is_directory(CORPUS))
        GTEST_SKIP() << CORPUS << " is missing: assimp-testmodels is not installed";
    for (const auto& [name, rule] : rules())
        EXPECT_TRUE(fs::is_regular_file(CORPUS / name)) << name;
}

}  // namespace
