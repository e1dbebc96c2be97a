// `vkpath render --samples FIRST:COUNT` and `vkpath merge`: parts of one
// render merged equal the render of their union, up to the rounding of the
// parts' float means; parts that overlap, leave gaps or come from another
// image are refused with one line and exit code 2, and nothing is written.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "image/image.h"
#include "support/exr_metadata.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;

std::string box() {
    return test::sourcePath("assets/cornell_box_diffuse.gltf").string();
}

// Renders `flags` of the box into dir/name.exr (with its variance AOV).
std::string render(const test::TempDir& dir, const std::string& name, const std::string& flags) {
    const std::string path = (dir / (name + ".exr")).string();
    const auto r =
        test::runVkpath("render " + box() + " -d 24x18 --aov variance -o " + path + " " + flags);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return path;
}

// The largest |a - b| / |b| over every pixel and channel where b is not 0
// (and |a - b| itself where it is).
double largestRelativeDifference(const image::Image& a, const image::Image& b) {
    double worst = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = std::abs(double(a.pixels[i][c]) - double(b.pixels[i][c]));
            worst =
                std::max(worst, b.pixels[i][c] != 0.0f ? d / std::abs(double(b.pixels[i][c])) : d);
        }
    return worst;
}

// The parts' means are floats: each is within half an ulp (2^-24 relative)
// of its exact value, and the merge adds them in double, so the merged mean
// is within about 2^-23 of the single render's own float mean; 8 ulps
// (2^-20, 9.5e-7) leaves room for the Kahan sums' last bits. Measured: 1.3e-7
// at worst on this film, about one ulp. The variance AOV is merged through
// sum-of-squares = n (v (n - 1) + m^2) and loses more where the variance is
// small against the mean squared: 1e-4 relative (measured 4.2e-6).
constexpr double MEAN_BOUND = 9.5367431640625e-7;
constexpr double VARIANCE_BOUND = 1e-4;

TEST(Merge, PartsMergedEqualTheWholeRender) {
    const test::TempDir dir;
    const std::string whole = render(dir, "whole", "-s 6");
    const std::string a = render(dir, "a", "--samples 0:2");
    const std::string b = render(dir, "b", "--samples 2:4");
    const std::string merged = (dir / "merged.exr").string();
    const auto r =
        test::runVkpath("merge " + b + " " + a + " -o " + merged + " --aov variance");  // any order
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::vkpathMetadata(merged)["vkpath:spp"], "6");
    EXPECT_EQ(test::vkpathMetadata(merged)["vkpath:firstSample"], "0");
    EXPECT_EQ(test::vkpathMetadata(a)["vkpath:firstSample"], "0");
    EXPECT_EQ(test::vkpathMetadata(b)["vkpath:firstSample"], "2");

    const double meanError =
        largestRelativeDifference(image::readImage(merged), image::readImage(whole));
    const double varianceError =
        largestRelativeDifference(image::readImage((dir / "merged.variance.exr").string()),
                                  image::readImage((dir / "whole.variance.exr").string()));
    EXPECT_LE(meanError, MEAN_BOUND);
    EXPECT_LE(varianceError, VARIANCE_BOUND);
    RecordProperty("meanRelativeError", fmt::format("{:.3g}", meanError));
    RecordProperty("varianceRelativeError", fmt::format("{:.3g}", varianceError));
    // The parts are not the whole: the bound is not met by any two renders.
    EXPECT_GT(largestRelativeDifference(image::readImage(a), image::readImage(whole)),
              100 * MEAN_BOUND);
}

TEST(Merge, MismatchedPartsAreOneLineAndNothingWritten) {
    const test::TempDir dir;
    const std::string a = render(dir, "a", "--samples 0:2");
    const std::string overlapping = render(dir, "overlapping", "--samples 1:2");
    const std::string afterGap = render(dir, "after_gap", "--samples 3:1");
    const std::string otherSeed = render(dir, "other_seed", "--samples 2:2 --seed 9");
    const std::string otherScene = (dir / "other_scene.exr").string();
    ASSERT_EQ(test::runVkpath("render " + test::sourcePath("assets/cornell_box.gltf").string() +
                              " -d 24x18 --samples 2:2 -o " + otherScene)
                  .exitCode,
              0);
    // The samples after a's, as a build before JSON settings wrote them:
    // its vkpath:settings are "key=value" words.
    const std::string next = render(dir, "next", "--samples 2:2");
    const std::string older = (dir / "older.exr").string();
    image::Metadata metadata;
    for (const auto& [key, value] : test::vkpathMetadata(next))
        metadata.emplace_back(
            key, key == "vkpath:settings" ? "size=24x18 max-depth=8 light-samples=1" : value);
    image::writeExr(older, image::readImage(next), metadata);
    ASSERT_EQ(
        test::runVkpath("merge " + a + " " + next + " -o " + (dir / "fine.exr").string()).exitCode,
        0);

    const std::string merged = (dir / "merged.exr").string();
    for (const std::string& other : {overlapping, afterGap, otherSeed, otherScene, a, older,
                                     test::sourcePath("assets/sky.hdr").string()}) {
        SCOPED_TRACE(other);
        const auto r = test::runVkpath("merge " + a + " " + other + " -o " + merged);
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
        EXPECT_FALSE(std::filesystem::exists(merged));
        if (other == older) {
            EXPECT_NE(r.err.find("written by an older vkpath build"), std::string::npos) << r.err;
        }
        if (other == otherSeed) {
            EXPECT_NE(r.err.find("seed=9 against seed=0"), std::string::npos) << r.err;
        }
    }
    // A gap is accepted when asked for: 3 samples of 0..3.
    const auto r =
        test::runVkpath("merge " + a + " " + afterGap + " -o " + merged + " --allow-gaps");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::vkpathMetadata(merged)["vkpath:spp"], "3");
}

TEST(Merge, BadSampleRangesAreOneLine) {
    for (const char* flags : {"--samples 3", "--samples 2:0", "--samples a:b", "-s 4 --samples 0:4",
                              "--samples 4294967295:2"}) {
        SCOPED_TRACE(flags);
        const auto r =
            test::runVkpath("render " + box() + " -d 8x8 " + std::string(flags) + " -o /dev/null");
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    }
}

}  // namespace

// Adaptive parts (each pixel its own count, a prefix of the part's range):
// merged by each pixel's counts from their spp AOVs, into the mean of all
// the pixel's samples; a part without its spp AOV is refused.
TEST(Merge, AdaptivePartsAreWeightedPerPixel) {
    const test::TempDir dir;
    const std::string flags = "--adaptive --adaptive-warmup 4 --target-error 0.002 --aov spp ";
    const std::string a = render(dir, "a", flags + "--samples 0:64");
    const std::string b = render(dir, "b", flags + "--samples 64:64");
    const std::string merged = (dir / "merged.exr").string();
    const auto r =
        test::runVkpath("merge " + a + " " + b + " --aov variance --aov spp -o " + merged);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const image::Image ma = image::readImage(a), mb = image::readImage(b);
    const image::Image na = image::readImage((dir / "a.spp.exr").string()),
                       nb = image::readImage((dir / "b.spp.exr").string());
    const image::Image m = image::readImage(merged),
                       n = image::readImage((dir / "merged.spp.exr").string());
    bool unequal = false;
    for (size_t i = 0; i < m.pixels.size(); ++i) {
        EXPECT_EQ(n.pixels[i].x, na.pixels[i].x + nb.pixels[i].x);
        unequal |= na.pixels[i].x != na.pixels[0].x;
        for (int c = 0; c < 3; ++c) {
            const double expected = (double(ma.pixels[i][c]) * na.pixels[i].x +
                                     double(mb.pixels[i][c]) * nb.pixels[i].x) /
                                    (na.pixels[i].x + nb.pixels[i].x);
            EXPECT_NEAR(m.pixels[i][c], expected, MEAN_BOUND * std::max(1.0, expected));
        }
    }
    EXPECT_TRUE(unequal) << "the parts were not adaptive";
    const auto metadata = test::vkpathMetadata(merged);
    EXPECT_EQ(metadata.at("vkpath:sampleRange"), "128");
    EXPECT_EQ(metadata.count("vkpath:estimatedRelMse"), 0u);

    std::filesystem::remove(dir / "b.spp.exr");
    const auto refused = test::runVkpath("merge " + a + " " + b + " -o " + merged);
    EXPECT_EQ(refused.exitCode, 2);
    EXPECT_EQ(test::lineCount(refused.err), 1) << refused.err;
    EXPECT_NE(refused.err.find("its spp AOV"), std::string::npos) << refused.err;
}
