// The render flags' effect on the loaded scene: the command line replaces
// what the scene file says only where a flag is given.
#include "app/render_options.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <iterator>
#include <nlohmann/json.hpp>

#include "input_error.h"
#include "shared/dimensions.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;

app::RenderOptions skySpheres() {
    app::RenderOptions o;
    o.scene = test::sourcePath("assets/sky_spheres.gltf").string();
    return o;
}

TEST(RenderOptions, SceneEnvironmentIsKeptWithoutFlags) {
    const scene::Scene s = app::loadRenderScene(skySpheres());
    ASSERT_TRUE(s.environment && s.environment->map);
    EXPECT_FLOAT_EQ(s.environment->strength, 1.0f);
    EXPECT_FLOAT_EQ(s.environment->rotationDegrees, 0.0f);
}

TEST(RenderOptions, FlagsReplaceTheSceneEnvironment) {
    app::RenderOptions o = skySpheres();
    o.environmentStrength = 0.25f;
    o.environmentRotation = 90.0f;
    scene::Scene s = app::loadRenderScene(o);
    ASSERT_TRUE(s.environment && s.environment->map);
    EXPECT_FLOAT_EQ(s.environment->strength, 0.25f);
    EXPECT_FLOAT_EQ(s.environment->rotationDegrees, 90.0f);

    o.environmentColor = {1, 2, 3};
    s = app::loadRenderScene(o);
    ASSERT_TRUE(s.environment);
    EXPECT_FALSE(s.environment->map);
    EXPECT_EQ(s.environment->color, glm::vec3(1, 2, 3));
    EXPECT_FLOAT_EQ(s.environment->strength, 0.25f);
}

// The message CLI11 ends the parse of `flags` (after a scene) with, as
// `vkpath render` would print it; empty when they parse.
std::string parseError(const std::string& flags) {
    CLI::App app;
    app::RenderOptions o;
    app::addRenderOptions(app, o);
    try {
        app.parse(test::sourcePath("assets/sky_spheres.gltf").string() + " " + flags, false);
    } catch (const CLI::ParseError& e) {
        return e.what();
    }
    return {};
}

// Each flag's values are checked by its validator as the command line is
// parsed: flags that would run for hours before a sample (-m, -l beyond
// 1024), or write nonsense, end the parse with one line naming the flag
// (exit code 2 on the command line), before any scene is read.
TEST(RenderOptions, FlagsOutOfRangeEndTheParseNamingTheFlag) {
    EXPECT_EQ(parseError(
                  fmt::format("-m {} -l {} --clamp 0 --regularize 1 --guide-spheres 0.5 -d 16384x1",
                              app::MAX_DEPTH, app::MAX_LIGHT_SAMPLES)),
              "");
    const std::pair<const char*, const char*> cases[] = {
        {"-m 1025", "--max-depth: Value 1025 not in range 0 to 1024"},
        {"-l 100000", "--light-samples: Value 100000 not in range 0 to 1024"},
        {"--clamp nan", "--clamp: 'nan' is not a finite number >= 0"},
        {"--clamp -1", "--clamp: '-1' is not a finite number >= 0"},
        {"--clamp 1e39", "--clamp: '1e39' is not a finite number >= 0"},  // beyond a float
        {"--regularize 1.5", "--regularize: '1.5' is not a number in [0, 1]"},
        {"--guide-spheres 1", "--guide-spheres: '1' is not a number in [0, 1)"},
        {"--guide-spheres nan", "--guide-spheres: 'nan' is not a number in [0, 1)"},
        {"--env-strength -1", "--env-strength: '-1' is not a finite number >= 0"},
        {"--env-rotate inf", "--env-rotate: 'inf' is not a finite number"},
        {"--megakernel-paths 0", "--megakernel-paths: Value 0 not in range 1 to 4294967295"},
        {"--max-wave-ms 0", "--max-wave-ms: '0' is not a finite number > 0"},
        {"--max-device-memory inf", "--max-device-memory: 'inf' is not a finite number > 0"},
        {"-d 0x10", "--size: film size '0x10' is not WxH with sides from 1 to 16384"},
        {"-d 640", "--size: film size '640' is not WxH with sides from 1 to 16384"},
        {"-e no_such.exr", "--env: File does not exist: no_such.exr"},
    };
    for (const auto& [flags, says] : cases) EXPECT_EQ(parseError(flags), says) << flags;
}

// A render's settings are a JSON object that ends with the estimator's
// version, so that a checkpoint or a merge part from a build of another
// version is refused; the first difference names a key one side lacks as
// "nothing". Settings as builds before JSON wrote them are no record.
TEST(RenderOptions, SettingsCarryTheEstimatorVersion) {
    const app::RenderOptions o = skySpheres();
    const std::string settings = app::renderIdentity(o, app::loadRenderScene(o)).settings;
    EXPECT_TRUE(app::isSettingsRecord(settings)) << settings;
    auto record = nlohmann::ordered_json::parse(settings);
    ASSERT_TRUE(record.is_object());
    EXPECT_EQ(record.items().begin().key(), "size") << settings;
    EXPECT_EQ(std::prev(record.end()).key(), "estimator") << settings;
    EXPECT_EQ(record["estimator"], VKP_ESTIMATOR_VERSION) << settings;
    const std::string version = "estimator=" + std::to_string(VKP_ESTIMATOR_VERSION);
    record.erase("estimator");
    const std::string older = record.dump();
    EXPECT_EQ(app::firstSettingDifference(older, settings),
              std::make_pair(std::string("nothing"), version));
    EXPECT_EQ(app::firstSettingDifference(settings, older),
              std::make_pair(version, std::string("nothing")));
    EXPECT_EQ(app::firstSettingDifference(settings, settings),
              std::make_pair(std::string(), std::string()));
    EXPECT_EQ(app::firstSettingDifference(R"({"a":1,"b":"x","c":3})", R"({"a":1,"b":"y","c":3})"),
              std::make_pair(std::string("b=x"), std::string("b=y")));
    EXPECT_EQ(app::firstSettingDifference(R"({"a":1,"b":2.5})", R"({"a":1,"b":0.1})"),
              std::make_pair(std::string("b=2.5"), std::string("b=0.1")));
    EXPECT_FALSE(app::isSettingsRecord("size=640x480 max-depth=8 estimator=1"));
    EXPECT_FALSE(app::isSettingsRecord("[1, 2]"));
}

// Flags that are floats are written as typed: 0.1 as 0.1, not as the
// float's 0.10000000149011612.
TEST(RenderOptions, SettingsKeepFloatsAsWritten) {
    app::RenderOptions o = skySpheres();
    o.clamp = 0.1f;
    o.environmentColor = {0.5f, 1.0f, 2.0f};
    const auto record =
        nlohmann::ordered_json::parse(app::renderIdentity(o, app::loadRenderScene(o)).settings);
    EXPECT_EQ(record.at("clamp").dump(), "0.1");
    EXPECT_EQ(record.at("env-color").dump(), "[0.5,1.0,2.0]");
    EXPECT_EQ(record.at("env-strength"), "scene");
}

}  // namespace
