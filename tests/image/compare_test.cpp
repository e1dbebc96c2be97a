// Image metrics on hand-made images whose values are worked out by hand, and
// the compare command's bounds, JSON and errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "image/metrics.h"
#include "input_error.h"
#include "support/run_vkpath.h"

namespace {

using namespace vkpath;

// b = [(1,1,1), (0,0,0)], a = [(1.5,1,1), (0,0,0.1)]:
//   R: differences 0.5, 0      G: none      B: differences 0, 0.1
image::Image imageA() {
    image::Image a(2, 1);
    a.pixels = {{1.5f, 1, 1}, {0, 0, 0.1f}};
    return a;
}
image::Image imageB() {
    image::Image b(2, 1);
    b.pixels = {{1, 1, 1}, {0, 0, 0}};
    return b;
}

TEST(Metrics, HandComputedValues) {
    const auto m = image::compareImages(imageA(), imageB());
    const auto& r = m.channels[0];
    EXPECT_NEAR(r.rmse, std::sqrt(0.125), 1e-7);
    EXPECT_NEAR(r.mae, 0.25, 1e-7);
    EXPECT_NEAR(r.relMse, 0.25 / 1.01 / 2, 1e-7);
    EXPECT_NEAR(r.maxError, 0.5, 1e-7);
    EXPECT_EQ(r.maxX, 0u);
    EXPECT_TRUE(std::isinf(m.channels[1].psnr));
    const auto& b = m.channels[2];
    EXPECT_NEAR(b.relMse, 0.01 / 0.01 / 2, 1e-6);
    EXPECT_EQ(b.maxX, 1u);
    EXPECT_NEAR(m.overall.rmse, std::sqrt(0.26 / 6), 1e-7);
    EXPECT_NEAR(m.overall.relMse, (0.25 / 1.01 + 1.0) / 6, 1e-6);
    EXPECT_NEAR(m.overall.mae, 0.1, 1e-7);
    EXPECT_NEAR(m.overall.psnr, 10 * std::log10(6 / 0.26), 1e-5);
    EXPECT_EQ(m.comparedPixels, 2u);
}

// The trimmed relMSE leaves out the 0.1% of pixels with the largest error:
// on 100 x 100 pixels, the 10 worst. One firefly among otherwise equal
// pixels dominates relMSE and vanishes from the trimmed one; with no
// outliers the two agree; a pair estimate trims the same way.
TEST(Metrics, TrimmedRelMseDropsTheWorstPixels) {
    image::Image reference(100, 100), render(100, 100);
    for (auto& p : reference.pixels) p = glm::vec3(0.5f);
    for (size_t i = 0; i < render.pixels.size(); ++i)
        render.pixels[i] = glm::vec3(i % 2 ? 0.55f : 0.45f);
    const double uniform =
        0.05 * 0.05 / (0.25 + image::RELMSE_EPSILON);  // to float rounding of 0.45, 0.55
    const double tolerance = 1e-6 * uniform;
    auto m = image::compareImages(render, reference);
    EXPECT_NEAR(m.overall.relMse, uniform, tolerance);
    EXPECT_NEAR(m.overall.relMseTrimmed, uniform, tolerance);
    for (int k = 0; k < 10; ++k) render.pixels[k * 997] = glm::vec3(1e4f);  // ten fireflies
    m = image::compareImages(render, reference);
    EXPECT_GT(m.overall.relMse, 1e3);
    EXPECT_NEAR(m.overall.relMseTrimmed, uniform, tolerance);
    render.pixels[5] = glm::vec3(1e4f);  // an eleventh stays in
    EXPECT_GT(image::compareImages(render, reference).overall.relMseTrimmed, 1);
    const auto pair = image::estimateErrorFromPair(render, reference);
    EXPECT_GT(pair.relMse, pair.relMseTrimmed);
}

TEST(Metrics, NonFinitePixelsAreCountedNotMeasured) {
    image::Image a = imageA();
    a.pixels[1].y = std::nanf("");
    const auto m = image::compareImages(a, imageB());
    EXPECT_EQ(m.nonFiniteA, 1u);
    EXPECT_EQ(m.comparedPixels, 1u);
    EXPECT_NEAR(m.overall.mae, 0.5 / 3, 1e-7);
}

TEST(Metrics, SizeMismatchIsAnInputError) {
    EXPECT_THROW(image::compareImages(image::Image(2, 1), image::Image(1, 2)), InputError);
}

class CompareCommand : public testing::Test {
  protected:
    void SetUp() override {
        m_dir =
            std::filesystem::temp_directory_path() / ("vkpath-compare-" + std::to_string(getpid()));
        std::filesystem::create_directories(m_dir);
        image::writeExr(m_dir / "a.exr", imageA());
        image::writeExr(m_dir / "b.exr", imageB());
        image::writeExr(m_dir / "small.exr", image::Image(1, 1));
    }
    void TearDown() override { std::filesystem::remove_all(m_dir); }
    std::string path(const char* name) const { return (m_dir / name).string(); }
    std::filesystem::path m_dir;
};

TEST_F(CompareCommand, JsonAndBounds) {
    const auto r = test::runVkpath("compare " + path("a.exr") + " " + path("b.exr") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto json = nlohmann::json::parse(r.out);
    EXPECT_NEAR(json["overall"]["mae"].get<double>(), 0.1, 1e-7);
    EXPECT_NEAR(json["R"]["rmse"].get<double>(), std::sqrt(0.125), 1e-7);

    const double relMse = (0.25 / 1.01 + 1.0) / 6;
    EXPECT_EQ(test::runVkpath("compare " + path("a.exr") + " " + path("b.exr") + " --max-relmse " +
                              std::to_string(relMse * 1.01))
                  .exitCode,
              0);
    EXPECT_EQ(test::runVkpath("compare " + path("a.exr") + " " + path("b.exr") + " --max-relmse " +
                              std::to_string(relMse * 0.99))
                  .exitCode,
              1);
    EXPECT_EQ(test::runVkpath("compare " + path("a.exr") + " " + path("a.exr") + " --max-rmse 0")
                  .exitCode,
              0);
}

TEST_F(CompareCommand, HeatmapIsWritten) {
    const auto r = test::runVkpath("compare " + path("a.exr") + " " + path("b.exr") +
                                   " --heatmap " + path("h.png"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const image::Image heat = image::readImage(m_dir / "h.png");
    EXPECT_EQ(heat.width, 2u);
    // The pixel with the larger relative error is brighter in the ramp's green/yellow.
    EXPECT_NE(heat.pixels[0], heat.pixels[1]);
}

TEST_F(CompareCommand, BadInputIsOneLineAndExitTwo) {
    for (const std::string& args : {"compare " + path("a.exr") + " " + path("small.exr"),
                                    "compare " + path("a.exr") + " " + path("missing.exr"),
                                    "compare " + path("a.exr") + " " + m_dir.string()}) {
        SCOPED_TRACE(args);
        const auto r = test::runVkpath(args);
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
        EXPECT_TRUE(r.out.empty());
    }
}

}  // namespace
