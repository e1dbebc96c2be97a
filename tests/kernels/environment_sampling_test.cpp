// Environment-map importance sampling on the GPU: samples follow
// luminance x sin(theta) (chi-square), the pdf of a sample equals the pdf
// looked up for its direction, no bright texel has probability 0, and the
// extreme sky (a 0.5 degree sun at 10^5 and 10^7 times the sky) stays exact.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "scene/environment_table.h"
#include "shared/environment_sampling.h"
#include "support/direction_chi2.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;

struct EnvTestResult {
    glm::vec3 direction;
    float pdf;
    float pdfLookup;
    uint32_t texel;
    uint32_t lookedUpTexel;
};

struct EnvPush {
    shared::EnvironmentInfo info;
    uint32_t count;
    uint32_t seed;
    uint32_t largest;  // 1: every random word is 2^32 - 1
};

constexpr uint32_t SAMPLES = 1000000;
// chi-square tests in this file: constant 3x2, constant 100x100, gradient,
// rotated gradient, sky 1e5, sky 1e7, power check (not counted: must reject).
const double ALPHA = test::sidakAlpha(0.01, 6);

shared::EnvironmentInfo infoFor(const image::Image& map, float rotationDegrees = 0) {
    shared::EnvironmentInfo info{};
    info.width = map.width;
    info.height = map.height;
    info.strength = 1;
    info.cosRotation = std::cos(glm::radians(rotationDegrees));
    info.sinRotation = std::sin(glm::radians(rotationDegrees));
    return info;
}

std::vector<EnvTestResult> sample(const scene::EnvironmentTable& table, const shared::EnvironmentInfo& info,
                                  uint32_t count = SAMPLES, bool largestUniforms = false) {
    vk::Context& context = test::context();
    vk::Buffer entries = vk::Buffer::fromSpan(context, std::span(table.entries));
    vk::Buffer results(context, count * sizeof(EnvTestResult));
    vk::Kernel kernel(context, "environment_sampling");
    kernel.dispatch(count, {{0, &entries}, {1, &results}}, EnvPush{info, count, 3, largestUniforms ? 1u : 0u});
    return results.download<EnvTestResult>();
}

// The pdf of a world direction, from the CPU side of the same shared code.
double pdfOf(const scene::EnvironmentTable& table, const shared::EnvironmentInfo& info, glm::vec3 d) {
    const glm::vec2 uv = shared::equirectUv(shared::envWorldToMap(info, d));
    return shared::envDirectionPdf(info, table.entries[shared::envTexelOfUv(info, uv)].probability, d);
}

// The integral over the sphere of directions of pdfOf, in the map's own
// coordinates: dw = 2 pi^2 sin(theta) du dv. The integrand is constant over
// each texel (the pdf is uniform in (u, v) inside a texel), so k x k
// midpoints per texel integrate it exactly but for float rounding: a pdf
// whose 1/sin(theta) or W H factor were wrong, or a lookup that picked the
// wrong texel, would show. (The (phi, cos theta) grid of the chi-square
// tests cuts texels anywhere and resolves the poles' 1/sin(theta) poorly:
// it integrates these pdfs only to ~2e-3.)
double integrateInMapCoordinates(const scene::EnvironmentTable& table, const shared::EnvironmentInfo& info,
                                 uint32_t k = 2) {
    const uint32_t nu = info.width * k, nv = info.height * k;
    double sum = 0;
    for (uint32_t j = 0; j < nv; ++j) {
        const double v = (j + 0.5) / nv, sinTheta = std::sin(std::numbers::pi * v);
        double row = 0;
        for (uint32_t i = 0; i < nu; ++i) {
            const glm::vec3 map = shared::equirectDirection(float((i + 0.5) / nu), float(v));
            row += pdfOf(table, info, shared::envMapToWorld(info, map));
        }
        sum += row * 2 * std::numbers::pi * std::numbers::pi * sinTheta / (double(nu) * nv);
    }
    return sum;
}

// The pdf a sample reports equals the pdf looked up for its direction, and
// the direction lands in the texel the table chose except within rounding of
// a texel edge: at most 1 sample in 1000 (measured: 0 to ~400 per 10^6 on
// lavapipe, depending on texel size).
void expectPdfsAgree(const std::vector<EnvTestResult>& results) {
    size_t moved = 0;
    for (const auto& r : results) {
        ASSERT_GT(r.pdf, 0.0f);
        ASSERT_NEAR(r.pdfLookup, r.pdf, 1e-4f * r.pdf) << "texel " << r.texel;
        moved += r.lookedUpTexel != r.texel;
    }
    EXPECT_LE(moved, results.size() / 1000) << moved << " samples left their texel";
}

void expectDirectionsFit(const scene::EnvironmentTable& table, const shared::EnvironmentInfo& info,
                         const std::vector<EnvTestResult>& results) {
    test::DirectionGrid grid;
    auto pdf = [&](glm::vec3 d) { return pdfOf(table, info, d); };
    EXPECT_NEAR(integrateInMapCoordinates(table, info), 1.0, 1e-3) << "pdf does not integrate to 1";
    EXPECT_NEAR(test::integrateOverSphere(grid, pdf), 1.0, 2e-3) << "the chi-square's expected counts";
    std::vector<glm::vec3> directions;
    for (const auto& r : results) directions.push_back(r.direction);
    const auto chi = test::chiSquareDirections(grid, directions, pdf);
    EXPECT_GT(chi.pValue, ALPHA) << "chi2 " << chi.statistic << " dof " << chi.degreesOfFreedom;
}

image::Image constantMap(uint32_t w, uint32_t h) {
    image::Image map(w, h);
    for (auto& p : map.pixels) p = glm::vec3(0.7f, 0.5f, 0.2f);
    return map;
}

image::Image gradientMap(uint32_t w, uint32_t h) {
    image::Image map(w, h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            map.at(x, y) = glm::vec3(0.1f + float(x) / w, 0.2f + 2.0f * float(y) / h, 0.5f);
    return map;
}

TEST(EnvironmentSampling, ConstantMaps) {
    for (auto size : {glm::uvec2(3, 2), glm::uvec2(100, 100)}) {
        SCOPED_TRACE(testing::Message() << size.x << "x" << size.y);
        const image::Image map = constantMap(size.x, size.y);
        const auto table = scene::buildEnvironmentTable(map);
        const auto info = infoFor(map);
        const auto results = sample(table, info);
        expectPdfsAgree(results);
        expectDirectionsFit(table, info, results);
    }
}

TEST(EnvironmentSampling, SmoothGradientAndRotation) {
    const image::Image map = gradientMap(64, 32);
    const auto table = scene::buildEnvironmentTable(map);
    for (float rotation : {0.0f, 73.0f}) {
        SCOPED_TRACE(rotation);
        const auto info = infoFor(map, rotation);
        const auto results = sample(table, info);
        expectPdfsAgree(results);
        expectDirectionsFit(table, info, results);
    }
}

TEST(EnvironmentSampling, ChiSquareRejectsAWrongMap) {
    // Samples of the gradient judged against a constant map's pdf must fail.
    const image::Image map = gradientMap(64, 32);
    const auto info = infoFor(map);
    const auto results = sample(scene::buildEnvironmentTable(map), info);
    const auto constant = scene::buildEnvironmentTable(constantMap(64, 32));
    std::vector<glm::vec3> directions;
    for (const auto& r : results) directions.push_back(r.direction);
    EXPECT_LT(test::chiSquareDirections({}, directions, [&](glm::vec3 d) { return pdfOf(constant, info, d); }).pValue,
              1e-10);
}

TEST(EnvironmentSampling, OneHotMapSamplesOnlyItsTexel) {
    image::Image map(100, 10);
    const uint32_t hot = 4 * 100 + 37;
    map.pixels[hot] = glm::vec3(5.0f);
    const auto table = scene::buildEnvironmentTable(map);
    for (size_t i = 0; i < table.entries.size(); ++i)
        ASSERT_EQ(table.entries[i].probability, i == hot ? 1.0f : 0.0f) << i;
    const auto info = infoFor(map);
    const auto results = sample(table, info, 100000);
    for (const auto& r : results) {
        ASSERT_EQ(r.texel, hot);
        const glm::vec2 uv = shared::equirectUv(r.direction);
        ASSERT_EQ(shared::envTexelOfUv(info, uv), hot);
    }
    expectPdfsAgree(results);
    EXPECT_NEAR(integrateInMapCoordinates(table, info, 8), 1.0, 1e-3);
}

// A 2048x1024 sky: a smooth gradient with a 0.5 degree sun `ratio` times brighter.
image::Image skyWithSun(float ratio) {
    image::Image map(2048, 1024);
    const glm::vec3 sun = glm::normalize(glm::vec3(0.3f, 0.6f, -0.74f));
    const float cosSun = std::cos(glm::radians(0.25f));
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x) {
            const glm::vec3 d = shared::equirectDirection((x + 0.5f) / map.width, (y + 0.5f) / map.height);
            const float sky = d.y > 0 ? 0.3f + 0.7f * d.y : 0.05f;
            map.at(x, y) = glm::dot(d, sun) >= cosSun ? glm::vec3(ratio) : glm::vec3(0.4f, 0.6f, 1.0f) * sky;
        }
    return map;
}

// Texel-space chi-square: sampled texels against luminance x sin(theta)
// computed here in double (independently of the table), summed over 32 x 32
// blocks so that most cells are well populated.
void expectTexelsFollowLuminance(const image::Image& map, const std::vector<EnvTestResult>& results) {
    constexpr uint32_t BLOCK = 32;
    const uint32_t bw = map.width / BLOCK, bh = map.height / BLOCK;
    std::vector<double> expected(bw * bh, 0), observed(bw * bh, 0);
    double total = 0;
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x) {
            const double w = scene::luminance(map.at(x, y)) * std::sin(std::numbers::pi * (y + 0.5) / map.height);
            expected[(y / BLOCK) * bw + x / BLOCK] += w;
            total += w;
        }
    for (double& e : expected) e *= double(results.size()) / total;
    for (const auto& r : results) observed[(r.texel / map.width / BLOCK) * bw + (r.texel % map.width) / BLOCK] += 1;
    const auto chi = test::chiSquareTest(observed, expected);
    EXPECT_GT(chi.pValue, ALPHA) << "chi2 " << chi.statistic << " dof " << chi.degreesOfFreedom;
}

TEST(EnvironmentSampling, SkyWithSunAtExtremeRatios) {
    for (float ratio : {1e5f, 1e7f}) {
        SCOPED_TRACE(ratio);
        const image::Image map = skyWithSun(ratio);
        const auto table = scene::buildEnvironmentTable(map);
        // No texel with radiance > 0 has probability 0 (a float CDF fails this at 1e7).
        for (size_t i = 0; i < map.pixels.size(); ++i)
            if (scene::luminance(map.pixels[i]) > 0) {
                ASSERT_GT(table.entries[i].probability, 0.0f) << i;
            }
        const auto results = sample(table, infoFor(map));
        expectPdfsAgree(results);
        expectTexelsFollowLuminance(map, results);
        EXPECT_NEAR(integrateInMapCoordinates(table, infoFor(map)), 1.0, 1e-3) << "pdf does not integrate to 1";
    }
}

// The largest random words the GPU can draw (2^32 - 1, the uniform
// 1 - 2^-24) pick the last bucket and a finite unit direction, on maps whose
// sizes are not powers of two, and the sky. The point lies at the texel's far
// corner, where rounding may carry it into the next row or column: the pdf
// then comes from that texel (pdfTexel), so sampling and evaluation agree.
TEST(EnvironmentSampling, LargestUniformsStayInRangeOnTheGpu) {
    for (const image::Image& map : {constantMap(3, 2), gradientMap(100, 37), skyWithSun(1e7f)}) {
        SCOPED_TRACE(testing::Message() << map.width << "x" << map.height);
        const auto table = scene::buildEnvironmentTable(map);
        const auto results = sample(table, infoFor(map), 8, /*largestUniforms*/ true);
        for (const auto& r : results) {
            ASSERT_LT(r.texel, map.width * map.height);
            ASSERT_TRUE(std::isfinite(r.direction.x) && std::isfinite(r.direction.y) && std::isfinite(r.direction.z));
            ASSERT_NEAR(glm::length(r.direction), 1.0f, 1e-6f);
            ASSERT_GT(r.pdf, 0.0f);
            ASSERT_EQ(r.pdfLookup, r.pdf);
            const int dx = int(r.lookedUpTexel % map.width) - int(r.texel % map.width);
            const int dy = int(r.lookedUpTexel / map.width) - int(r.texel / map.width);
            ASSERT_TRUE((dx == 0 || dx == 1 || dx == 1 - int(map.width)) && (dy == 0 || dy == 1))
                << "texel " << r.texel << " looked up as " << r.lookedUpTexel;
        }
    }
}

TEST(EnvironmentSampling, LargestUniformsStayInRange) {
    EXPECT_EQ(shared::aliasBucket(0xffffffffu, 7u), 6u);
    EXPECT_EQ(shared::aliasBucket(0xffffffffu, 2048u * 1024u), 2048u * 1024u - 1);
    EXPECT_EQ(shared::aliasBucket(0u, 5u), 0u);
    const image::Image map = constantMap(4, 2);
    const auto info = infoFor(map);
    const float almostOne = 1.0f - std::ldexp(1.0f, -24);
    const auto s = shared::envSampleInTexel(info, 7, glm::vec2(almostOne));
    EXPECT_EQ(shared::envTexelOfUv(info, s.uv), 7u);
    EXPECT_EQ(s.pdfTexel, 7u);
    EXPECT_LT(s.uv.x, 1.0f);
    EXPECT_LT(s.uv.y, 1.0f);
}

TEST(EnvironmentSampling, TableProbabilitiesSumToOne) {
    const auto table = scene::buildEnvironmentTable(skyWithSun(1e7f));
    double sum = 0;
    for (const auto& e : table.entries) sum += e.probability;
    EXPECT_NEAR(sum, 1.0, 1e-6);
    EXPECT_TRUE(scene::buildEnvironmentTable(image::Image(8, 4)).entries.empty());  // black map: no sampling
}

}  // namespace
