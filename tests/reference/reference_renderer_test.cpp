// The CPU reference renderer against the GPU wavefront renderer.
//
// Same seed: both follow the same paths (the same random number for the same
// decision, the same shared math), so their images agree far beyond noise;
// they differ only where float rounding flips a discrete decision (see
// SameSeed.FollowsTheSamePaths for the bounds). Different seeds: a block z-test
// with the variance AOVs accepts GPU against CPU and rejects a CPU render
// whose light-selection pdf is 10% off, so the comparison has power.
#include "reference/reference_renderer.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "image/metrics.h"
#include "image/statistics.h"
#include "scene/load.h"
#include "support/gpu_render.h"
#include "support/pixel_match.h"
#include "support/test_context.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

wavefront::RenderSettings smallSettings(uint32_t spp, uint32_t seed) {
    wavefront::RenderSettings s;
    s.width = 48;
    s.height = 36;
    s.samplesPerPixel = spp;
    s.maxDepth = 8;
    s.lightSamples = 1;
    s.seed = seed;
    return s;
}

using test::renderGpu;

wavefront::RenderResult renderCpu(const scene::Scene& scene,
                                  const wavefront::RenderSettings& settings) {
    return reference::ReferenceRenderer(scene, settings).render();
}

scene::Scene loadTestScene(const std::string& name) {
    if (name == "CBspheres.dae") return scene::loadScene(test::sharedScene(name));
    return scene::loadScene(test::sourcePath("assets/" + name));
}

std::string sceneName(const testing::TestParamInfo<std::string>& param) {
    std::string name = std::filesystem::path(param.param).stem().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

const auto SCENES = testing::Values("cornell_box.gltf", "cornell_box_diffuse.gltf", "CBspheres.dae",
                                    "normal_maps.gltf");

// Per pixel, relMSE's term averaged over the channels: (a - b)^2 / (b^2 + 0.01).
std::vector<double> relMseTerms(const image::Image& a, const image::Image& b) {
    std::vector<double> terms(a.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        double sum = 0;
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.pixels[i][c]) - b.pixels[i][c];
            sum += d * d / (double(b.pixels[i][c]) * b.pixels[i][c] + image::RELMSE_EPSILON);
        }
        terms[i] = sum / 3;
    }
    return terms;
}

// relMSE over all pixels but the `fraction` with the largest terms.
double trimmedRelMse(const image::Image& a, const image::Image& b, double fraction) {
    std::vector<double> terms = relMseTerms(a, b);
    std::sort(terms.begin(), terms.end());
    const size_t keep = terms.size() - size_t(std::ceil(fraction * double(terms.size())));
    double sum = 0;
    for (size_t i = 0; i < keep; ++i) sum += terms[i];
    return keep > 0 ? sum / double(keep) : 0.0;
}

using test::matchingPixelFraction;

// Same seed, 48x36 pixels, 4 spp, depth 8: GPU (lavapipe) and CPU images.
//
// A path diverges only where rounding flips a discrete decision. The GPU's
// sin, cos and inversesqrt (disk and sphere sampling, every normalize) are
// not libm's, so directions differ by ulps; a decision flips where that
// matters: a grazing angle (a silhouette's cos(wo) changing sign), an edge or
// corner hit or missed, u < F at glass, u < survive in Russian roulette.
// Rendering both at 192x144, 1 spp (one path per pixel) with max depth 0
// to 8 shows where: at depth 0 (camera rays, first hits, emission) nothing
// differs; the diffuse box's paths first differ at depth 1 to 4 (12 of
// 27648, one of them a silhouette whose light sample the GPU saw at a
// grazing angle), the glass box's at depth 8 in 99 of 27648, clustered on
// the glass sphere where refraction amplifies the difference.
//
// What that does to these 48x36, 4 spp images, worst over seeds 1..20 (two
// renders with different seeds, for scale: relMSE 0.03 to 8, 0.028 or more
// without the 1% worst pixels; normal_maps, whose shading normals come from
// generated and given tangents and a bilinear normal map, 0.041 to 0.055
// and 0.032 or more):
//
//   scene                 pixels equal   relMSE      relMSE without the 1% worst pixels
//   cornell_box           98.55%         1.32        2.7e-5
//   cornell_box_diffuse   99.65%         4.2e-5      1.4e-14
//   CBspheres             100%           2.6e-12     7e-15
//   normal_maps           99.36%         3.2e-5      8.8e-11
//
// The full relMSE of the glass box is no stable statistic: in 2 of 20 seeds a
// diverged path carried a caustic firefly through the glass (one pixel
// changes by ~4) and relMSE reached 0.11 and 1.32, as large as independent
// noise; in the other 18 it stayed below 1.3e-3. So the bounds are:
//   - at least 97% of pixels equal (the worst seed had 98.55%);
//   - relMSE without the 1% worst pixels (18 of 1728, room for the diverged
//     ones) <= 1e-3: 37x the worst measured, 28x below independent noise;
//   - the full relMSE <= 1e-3 for the scenes without a chaotic glass path
//     (24x the worst measured).
// They fail when the renderers stop following the same paths (a dimension off
// by one, a dropped or doubled shadow contribution, a path lost between
// queues), not on noise: the test also checks that another seed fails them.
constexpr double SAME_SEED_MIN_MATCHING = 0.97;
constexpr double SAME_SEED_TRIM = 0.01;
constexpr double SAME_SEED_MAX_RELMSE = 1e-3;

// Where no diverged path was seen to carry a firefly (the table above).
bool fullRelMseIsStable(const std::string& scene) {
    return scene != "cornell_box.gltf";
}

class SameSeed : public testing::TestWithParam<std::string> {};

TEST_P(SameSeed, FollowsTheSamePaths) {
    if (GetParam() == std::string("CBspheres.dae")) VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadTestScene(GetParam());
    const auto settings = smallSettings(4, 7);
    const auto gpu = renderGpu(s, settings);
    const auto cpu = renderCpu(s, settings);
    EXPECT_EQ(cpu.samplesPerPixel, gpu.samplesPerPixel);
    EXPECT_EQ(cpu.nonFiniteSamples, gpu.nonFiniteSamples);

    const double matching = matchingPixelFraction(cpu.image, gpu.image);
    const double trimmed = trimmedRelMse(cpu.image, gpu.image, SAME_SEED_TRIM);
    const double full = image::compareImages(cpu.image, gpu.image).overall.relMse;
    EXPECT_GE(matching, SAME_SEED_MIN_MATCHING);
    EXPECT_LE(trimmed, SAME_SEED_MAX_RELMSE);
    if (fullRelMseIsStable(GetParam())) {
        EXPECT_LE(full, SAME_SEED_MAX_RELMSE);
    }
    RecordProperty("matchingPixels", std::to_string(matching));
    RecordProperty("trimmedRelMse", std::to_string(trimmed));
    RecordProperty("relMse", std::to_string(full));

    // The same paths trace the same rays, but for the few whose decisions
    // rounding flips (at most 1 - SAME_SEED_MIN_MATCHING of the pixels).
    auto expectSameCount = [](uint64_t cpuCount, uint64_t gpuCount, const char* what) {
        EXPECT_GT(cpuCount, 0u) << what;
        EXPECT_NEAR(double(gpuCount), double(cpuCount),
                    (1 - SAME_SEED_MIN_MATCHING) * double(cpuCount))
            << what;
    };
    expectSameCount(cpu.rays.closest, gpu.rays.closest, "closest-hit rays");
    expectSameCount(cpu.rays.shadow, gpu.rays.shadow, "shadow rays");
    RecordProperty("closestRays", fmt::format("cpu {} gpu {}", cpu.rays.closest, gpu.rays.closest));
    RecordProperty("shadowRays", fmt::format("cpu {} gpu {}", cpu.rays.shadow, gpu.rays.shadow));

    // Another seed fails the first two bounds: they cannot be met by two
    // renders that merely estimate the same image.
    const auto other = renderCpu(s, smallSettings(4, 8));
    EXPECT_LT(matchingPixelFraction(other.image, gpu.image), SAME_SEED_MIN_MATCHING);
    EXPECT_GT(trimmedRelMse(other.image, gpu.image, SAME_SEED_TRIM), 10 * SAME_SEED_MAX_RELMSE);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SameSeed, SCENES, sceneName);

// The Sobol' sampler is the same shared code on both sides: with the same
// seed the renderers follow the same paths, within the bounds above (both
// scenes without a chaotic glass path). The independent sampler's image with
// that seed fails them, so the sampler reached both renderers.
TEST(SameSeedSobol, FollowsTheSamePaths) {
    for (const char* name : {"cornell_box_diffuse.gltf", "CBspheres.dae"}) {
        SCOPED_TRACE(name);
        // The bundled box has been checked by now; skipped, the test says why.
        if (name == std::string("CBspheres.dae")) VKPATH_SKIP_WITHOUT_SHARED_SCENES();
        const scene::Scene s = loadTestScene(name);
        auto settings = smallSettings(4, 7);
        settings.sampler = wavefront::SamplerKind::Sobol;
        const auto gpu = renderGpu(s, settings);
        const auto cpu = renderCpu(s, settings);
        EXPECT_GE(matchingPixelFraction(cpu.image, gpu.image), SAME_SEED_MIN_MATCHING);
        EXPECT_LE(trimmedRelMse(cpu.image, gpu.image, SAME_SEED_TRIM), SAME_SEED_MAX_RELMSE);
        EXPECT_LE(image::compareImages(cpu.image, gpu.image).overall.relMse, SAME_SEED_MAX_RELMSE);

        settings.sampler = wavefront::SamplerKind::Independent;
        const auto independent = renderCpu(s, settings);
        EXPECT_LT(matchingPixelFraction(independent.image, gpu.image), SAME_SEED_MIN_MATCHING);
        EXPECT_GT(trimmedRelMse(independent.image, gpu.image, SAME_SEED_TRIM),
                  10 * SAME_SEED_MAX_RELMSE);
    }
}

// The estimator is checked statistically with different seeds: 48x36 at 64
// spp, depth 3, 8x8 blocks (6 x 5 = 30), false-alarm rate 1% over all
// blocks (Sidak-corrected critical |z| 3.59). Measured over 5 seed pairs
// per scene, GPU against CPU: no block rejected, worst |z| 2.75
// (normal_maps: 1.58).
constexpr uint32_t ZTEST_SPP = 64;
constexpr uint32_t ZTEST_DEPTH = 3;

wavefront::RenderSettings ztestSettings(uint32_t seed) {
    auto s = smallSettings(ZTEST_SPP, seed);
    s.maxDepth = ZTEST_DEPTH;
    return s;
}

image::BlockComparison ztest(const wavefront::RenderResult& a, const wavefront::RenderResult& b) {
    return image::compareBlocks(a.image, a.varianceOfMean, b.image, b.varianceOfMean, 8, 0.01);
}

class DifferentSeeds : public testing::TestWithParam<std::string> {};

TEST_P(DifferentSeeds, GpuAndCpuEstimateTheSameImage) {
    if (GetParam() == std::string("CBspheres.dae")) VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = loadTestScene(GetParam());
    const auto gpu = renderGpu(s, ztestSettings(1));
    const auto cpu = renderCpu(s, ztestSettings(2));
    const auto c = ztest(gpu, cpu);
    EXPECT_EQ(c.blocks, 30);
    EXPECT_EQ(c.rejected, 0) << "worst |z| " << c.worstZ << " at " << c.worstX << "," << c.worstY
                             << ", critical " << c.critical << " over " << c.blocks << " blocks";
}

INSTANTIATE_TEST_SUITE_P(Scenes, DifferentSeeds, SCENES, sceneName);

// Power: the same CPU estimator with one light's selection probability off by
// 10% where the pdf reads it (light sampling's 1 / (choice x pdf) and both
// MIS weights), but not where the alias table samples it (threshold and
// alias are untouched): the estimate is biased by a few percent wherever
// that light matters, and the z-test must say so. Measured over 5 seed
// pairs: 9 to 12 of the 30 blocks rejected, worst |z| 7.2 to 9.2 against the
// critical 3.59. (In the noisier glass boxes the same error shows in 0 to 2
// blocks at this spp, which is why the power is shown on the diffuse box.)
TEST(StatisticalComparison, RejectsATenPercentPdfError) {
    const scene::Scene s = loadTestScene("cornell_box_diffuse.gltf");
    const auto gpu = renderGpu(s, ztestSettings(1));

    wavefront::SceneTables broken = wavefront::buildSceneTables(s);
    ASSERT_GE(broken.lightAlias.size(), 1u);
    // The light chosen most often: its error shows the most. (Among the power
    // table's entries, one per light: a light tree's part follows them.)
    size_t light = 0;
    for (size_t i = 1; i < broken.lights.size(); ++i)
        if (broken.lightAlias[i].probability > broken.lightAlias[light].probability) light = i;
    broken.lightAlias[light].probability *= 1.1f;
    const auto settings = ztestSettings(2);
    const reference::ReferenceRenderer wrong(std::move(broken), settings);
    const auto c = ztest(gpu, wrong.render());
    EXPECT_GT(c.rejected, 0) << "worst |z| " << c.worstZ << ", critical " << c.critical;

    // And the same tables unchanged are accepted: the rejection is the pdf's doing.
    const reference::ReferenceRenderer right(wavefront::buildSceneTables(s), settings);
    EXPECT_EQ(ztest(gpu, right.render()).rejected, 0);
}

TEST(Reference, ThreadCountDoesNotChangeTheImage) {
    const scene::Scene s = loadTestScene("cornell_box.gltf");
    auto settings = smallSettings(3, 5);
    settings.threads = 1;
    const auto one = renderCpu(s, settings);
    settings.threads = 3;
    const auto three = renderCpu(s, settings);
    ASSERT_EQ(one.image.pixels.size(), three.image.pixels.size());
    EXPECT_EQ(std::memcmp(one.image.pixels.data(), three.image.pixels.data(),
                          one.image.pixels.size() * sizeof(glm::vec3)),
              0);
    EXPECT_EQ(std::memcmp(one.varianceOfMean.pixels.data(), three.varianceOfMean.pixels.data(),
                          one.varianceOfMean.pixels.size() * sizeof(glm::vec3)),
              0);
    EXPECT_EQ(one.samplesPerPixel, 3u);
    EXPECT_EQ(one.paths, 48u * 36u * 3u);
}

// The image is the mean of the path samples, and the variance AOV the
// variance of that mean, computed from tracePath directly.
TEST(Reference, ImageAndVarianceAreThePathStatistics) {
    const scene::Scene s = loadTestScene("cornell_box_diffuse.gltf");
    const auto settings = smallSettings(5, 3);
    const reference::ReferenceRenderer renderer(s, settings);
    const auto r = renderer.render();
    wavefront::RayCounts rays;
    uint64_t rejected = 0;
    for (uint32_t pixel : {0u, 700u, 48u * 36u - 1u}) {
        glm::dvec3 sum(0), sumSquares(0);
        for (uint32_t i = 0; i < 5; ++i) {
            const glm::dvec3 l(renderer.tracePath(pixel, i, rays, rejected));
            sum += l;
            sumSquares += l * l;
        }
        for (int c = 0; c < 3; ++c) {
            const double mean = sum[c] / 5, variance = (sumSquares[c] - 5 * mean * mean) / 4;
            EXPECT_FLOAT_EQ(r.image.pixels[pixel][c], float(mean));
            EXPECT_NEAR(r.varianceOfMean.pixels[pixel][c], variance / 5, 1e-6 * (1 + variance));
        }
    }
}

// A path whose radiance is NaN or infinite is dropped and counted, not
// added (accumulate.comp's rule). A light selection probability of 0 that
// the sampler still picks makes the light sample 0 / 0.
TEST(Reference, NonFiniteSamplesAreDroppedAndCounted) {
    const scene::Scene s = loadTestScene("cornell_box_diffuse.gltf");
    wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    for (auto& entry : tables.lightAlias) entry.probability = 0.0f;
    auto settings = smallSettings(2, 4);
    settings.width = 16;
    settings.height = 12;
    const reference::ReferenceRenderer renderer(std::move(tables), settings);
    const auto r = renderer.render();
    uint64_t expectedDropped = 0, rejected = 0;
    wavefront::RayCounts rays;
    for (uint32_t pixel = 0; pixel < 16 * 12; ++pixel) {
        glm::dvec3 sum(0);
        for (uint32_t i = 0; i < 2; ++i) {
            const glm::vec3 l = renderer.tracePath(pixel, i, rays, rejected);
            if (std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z))
                sum += glm::dvec3(l);
            else
                ++expectedDropped;
        }
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(r.image.pixels[pixel][c], float(sum[c] / 2));
    }
    EXPECT_GT(expectedDropped, 0u);
    EXPECT_EQ(r.nonFiniteSamples, expectedDropped);
    // Every path of the render was traced again above: the same rays.
    EXPECT_EQ(r.rays.closest, rays.closest);
    EXPECT_EQ(r.rays.shadow, rays.shadow);
}

}  // namespace
