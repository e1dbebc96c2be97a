// Environment-map importance sampling on the GPU: samples follow the
// bilinear luminance x sin(theta) cell by cell (chi-square), the table's cells
// weigh what the bilinear radiance integrates to over them, the pdf of a
// sample equals the pdf looked up for its direction, no cell the radiance
// reaches has probability 0, light sampling alone integrates the bilinear
// radiance without bias, and the extreme sky (a 0.5 degree sun at 10^5 and
// 10^7 times the sky) stays exact.
#include "shared/environment_sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "image/statistics.h"
#include "scene/alias_table.h"
#include "scene/environment_table.h"
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
    glm::vec3 radiance;  // the bilinear radiance of the map in `direction`
};
static_assert(sizeof(EnvTestResult) == 40);  // as the kernel's scalar layout

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

std::vector<EnvTestResult> sample(const image::Image& map,
                                  const std::vector<shared::AliasEntry>& entries,
                                  const shared::EnvironmentInfo& info, uint32_t count = SAMPLES,
                                  bool largestUniforms = false) {
    vk::Context& context = test::context();
    vk::Buffer table = vk::Buffer::fromSpan(context, std::span(entries));
    vk::Buffer texels = vk::Buffer::fromSpan(context, std::span(map.pixels));
    vk::Buffer results(context, count * sizeof(EnvTestResult));
    vk::Kernel kernel(context, "environment_sampling");
    kernel.dispatch(count, {{0, &table}, {1, &results}, {2, &texels}},
                    EnvPush{info, count, 3, largestUniforms ? 1u : 0u});
    return results.download<EnvTestResult>();
}

std::vector<EnvTestResult> sample(const image::Image& map, const scene::EnvironmentTable& table,
                                  const shared::EnvironmentInfo& info, uint32_t count = SAMPLES,
                                  bool largestUniforms = false) {
    return sample(map, table.entries, info, count, largestUniforms);
}

// The map's bilinear radiance at map coordinates uv, through the shared
// lookup compiled as C++ (tests/scene/environment_test.cpp checks it against
// hand-computed values).
glm::vec3 bilinearAt(const image::Image& map, const shared::EnvironmentInfo& info, glm::vec2 uv) {
    const shared::EnvBilinear b = shared::envBilinear(info, uv);
    return shared::envBilinearMix(b, map.pixels[b.texel00], map.pixels[b.texel10],
                                  map.pixels[b.texel01], map.pixels[b.texel11]);
}

// The integral over texel (x, y)'s cell of the bilinear luminance x
// sin(theta) du dv, by the midpoint rule on k x k points (k even: the kinks of
// the bilinear function at the texel centre fall between points, so each
// quarter of the cell is a bilinear patch that the rule integrates exactly
// but for sin(theta)'s curvature, a relative error ~ (pi / 2kH)^2 / 6).
// Independent of the table's closed form, which it checks.
double cellIntegral(const image::Image& map, const shared::EnvironmentInfo& info, uint32_t x,
                    uint32_t y, uint32_t k) {
    double sum = 0;
    for (uint32_t j = 0; j < k; ++j) {
        const double v = (y + (j + 0.5) / k) / map.height;
        for (uint32_t i = 0; i < k; ++i) {
            const double u = (x + (i + 0.5) / k) / map.width;
            sum += scene::luminance(bilinearAt(map, info, glm::vec2(float(u), float(v)))) *
                   std::sin(std::numbers::pi * v);
        }
    }
    return sum / (double(k) * k * map.width * map.height);
}

// The pdf of a world direction, from the CPU side of the same shared code.
double pdfOf(const scene::EnvironmentTable& table, const shared::EnvironmentInfo& info,
             glm::vec3 d) {
    const glm::vec2 uv = shared::equirectUv(shared::envWorldToMap(info, d));
    return shared::envDirectionPdf(info, table.entries[shared::envTexelOfUv(info, uv)].probability,
                                   d);
}

// The integral over the sphere of directions of pdfOf, in the map's own
// coordinates: dw = 2 pi^2 sin(theta) du dv. The integrand is constant over
// each texel (the pdf is uniform in (u, v) inside a texel), so k x k
// midpoints per texel integrate it exactly but for float rounding: a pdf
// whose 1/sin(theta) or W H factor were wrong, or a lookup that picked the
// wrong texel, would show. (The (phi, cos theta) grid of the chi-square
// tests cuts texels anywhere and resolves the poles' 1/sin(theta) poorly:
// it integrates these pdfs only to ~2e-3.)
double integrateInMapCoordinates(const scene::EnvironmentTable& table,
                                 const shared::EnvironmentInfo& info, uint32_t k = 2) {
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
    EXPECT_NEAR(test::integrateOverSphere(grid, pdf), 1.0, 2e-3)
        << "the chi-square's expected counts";
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
        const auto results = sample(map, table, info);
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
        const auto results = sample(map, table, info);
        expectPdfsAgree(results);
        expectDirectionsFit(table, info, results);
    }
}

TEST(EnvironmentSampling, ChiSquareRejectsAWrongMap) {
    // Samples of the gradient judged against a constant map's pdf must fail.
    const image::Image map = gradientMap(64, 32);
    const auto info = infoFor(map);
    const auto results = sample(map, scene::buildEnvironmentTable(map), info);
    const auto constant = scene::buildEnvironmentTable(constantMap(64, 32));
    std::vector<glm::vec3> directions;
    for (const auto& r : results) directions.push_back(r.direction);
    EXPECT_LT(test::chiSquareDirections({}, directions,
                                        [&](glm::vec3 d) { return pdfOf(constant, info, d); })
                  .pValue,
              1e-10);
}

// One bright texel in a black map: its bilinear radiance reaches half a texel
// into the eight cells around its own, and those nine cells are all that
// light sampling may choose, in proportion to what the radiance integrates to
// over each. In u, by hand: the tent around the texel's centre covers its own
// cell with 3/4 of a texel's width and each neighbour's with 1/8 (half-way
// across, falling from 1/2 to 0), so a neighbour's cell in the same row has
// 1/6 of the probability. In v, where sin(theta) weighs in, against the
// midpoint rule.
TEST(EnvironmentSampling, OneHotMapSamplesTheCellsItsRadianceReaches) {
    image::Image map(100, 10);
    const int hx = 37, hy = 4;
    map.at(hx, hy) = glm::vec3(5.0f);
    const auto table = scene::buildEnvironmentTable(map);
    const auto info = infoFor(map);
    auto reached = [&](uint32_t texel) {
        return std::abs(int(texel % map.width) - hx) <= 1 &&
               std::abs(int(texel / map.width) - hy) <= 1;
    };
    for (uint32_t i = 0; i < table.entries.size(); ++i) {
        if (reached(i)) {
            ASSERT_GT(table.entries[i].probability, 0.0f) << i;
        } else {
            ASSERT_EQ(table.entries[i].probability, 0.0f) << i;
        }
    }
    auto probability = [&](int x, int y) {
        return double(table.entries[y * map.width + x].probability);
    };
    double total = 0;
    for (int y = hy - 1; y <= hy + 1; ++y)
        for (int x = hx - 1; x <= hx + 1; ++x) total += cellIntegral(map, info, x, y, 256);
    for (int y = hy - 1; y <= hy + 1; ++y) {
        SCOPED_TRACE(y);
        EXPECT_NEAR(probability(hx - 1, y) / probability(hx, y), 1.0 / 6, 1e-5);
        EXPECT_NEAR(probability(hx + 1, y) / probability(hx, y), 1.0 / 6, 1e-5);
        for (int x = hx - 1; x <= hx + 1; ++x) {
            const double expected = cellIntegral(map, info, x, y, 256) / total;
            EXPECT_NEAR(probability(x, y), expected, 1e-5 * expected) << x;
        }
    }
    const auto results = sample(map, table, info, 100000);
    for (const auto& r : results) {
        ASSERT_TRUE(reached(r.texel)) << r.texel;
        ASSERT_TRUE(reached(r.lookedUpTexel)) << r.lookedUpTexel;
    }
    expectPdfsAgree(results);
    EXPECT_NEAR(integrateInMapCoordinates(table, info, 8), 1.0, 1e-3);
}

// The table's closed-form cell weights are the integrals of the bilinear
// luminance x sin(theta) over the cells, on a small map with black texels
// beside bright ones, the wrap in u (a bright last column) and the clamped
// rows at both poles (bright first and last rows).
TEST(EnvironmentSampling, CellWeightsAreTheBilinearIntegrals) {
    image::Image map(7, 5);
    map.at(6, 0) = glm::vec3(4.0f, 1.0f, 0.5f);
    map.at(0, 2) = glm::vec3(0.0f, 2.0f, 0.0f);
    map.at(3, 2) = glm::vec3(1.0f);
    map.at(4, 2) = glm::vec3(8.0f, 8.0f, 8.0f);
    map.at(2, 4) = glm::vec3(0.5f, 0.5f, 3.0f);
    const auto table = scene::buildEnvironmentTable(map);
    const auto info = infoFor(map);
    std::vector<double> integrals;
    double total = 0;
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x) {
            integrals.push_back(cellIntegral(map, info, x, y, 256));
            total += integrals.back();
        }
    EXPECT_NEAR(table.totalWeight, total, 1e-5 * total);
    for (size_t i = 0; i < integrals.size(); ++i) {
        const double expected = integrals[i] / total;
        if (expected == 0) {
            EXPECT_EQ(table.entries[i].probability, 0.0f) << i;
        } else {
            EXPECT_NEAR(table.entries[i].probability, expected, 1e-5 * expected) << i;
        }
    }
    // By hand: the cells the bright texels reach, 3 x 3 around each, wrapped in
    // u and cut at the poles: 6 around (6, 0), 9 around (0, 2), 12 around
    // (3..4, 2) and 6 around (2, 4), less (6, 1), (0, 1), (5, 1), (1, 3), (2, 3)
    // and (3, 3), each reached twice.
    size_t positive = 0;
    for (const auto& e : table.entries) positive += e.probability > 0;
    EXPECT_EQ(positive, 27u);
}

// Light sampling alone (no BSDF sampling, no MIS weights) must estimate the
// irradiance E = integral of L(w) max(0, n.w) dw of the bilinear radiance
// without bias, on maps with sharp black/bright boundaries, where the radiance
// spills into black texels' cells: the mean of luminance(L) cos / pdf over
// 10^6 GPU samples (radiance, direction and pdf from the kernel) against E by
// the midpoint rule, a z-test on the sample's own standard error (Sidak over
// the four cases). The power check: a table weighted by each texel's own
// value at its centre (the nearest-texel lookup's table) leaves the spilled
// radiance to BSDF sampling, and alone it is rejected by far.
TEST(EnvironmentSampling, LightSamplingAloneIntegratesTheBilinearRadiance) {
    image::Image checker(16, 8), sun(32, 16);
    for (uint32_t y = 0; y < checker.height; ++y)
        for (uint32_t x = 0; x < checker.width; ++x)
            if ((x + y) % 2 == 0) checker.at(x, y) = glm::vec3(3.0f, 2.0f, 1.0f);
    sun.at(20, 5) = glm::vec3(1000.0f);
    // Up, and tilted towards the sun texel (20, 5) so that it lies in both hemispheres.
    const glm::dvec3 normals[] = {{0, 1, 0}, glm::normalize(glm::dvec3(-0.3, 0.5, 0.8))};
    const double critical = image::normalCritical(test::sidakAlpha(0.01, 4));

    for (const image::Image* map : {&checker, &sun}) {
        SCOPED_TRACE(testing::Message() << map->width << "x" << map->height);
        const auto info = infoFor(*map);
        const auto table = scene::buildEnvironmentTable(*map);
        const auto results = sample(*map, table, info);
        float brightest = 0;
        for (const glm::vec3& p : map->pixels) brightest = std::max(brightest, p.x);
        // The GPU's lookup is the CPU's (to float rounding of the mapping).
        for (const auto& r : results) {
            const glm::vec3 cpu = bilinearAt(*map, info, shared::equirectUv(r.direction));
            ASSERT_NEAR(r.radiance.x, cpu.x, 1e-4f * brightest);
            ASSERT_NEAR(r.radiance.y, cpu.y, 1e-4f * brightest);
        }
        std::vector<double> nearestWeights;
        for (uint32_t y = 0; y < map->height; ++y)
            for (uint32_t x = 0; x < map->width; ++x)
                nearestWeights.push_back(scene::luminance(map->at(x, y)) *
                                         std::sin(std::numbers::pi * (y + 0.5) / map->height));
        const auto nearestResults = sample(*map, scene::buildAliasTable(nearestWeights), info);

        for (const glm::dvec3& n : normals) {
            SCOPED_TRACE(testing::Message() << "normal " << n.x << " " << n.y << " " << n.z);
            // The midpoint rule with k x k points per texel (k even, so the kinks
            // of the bilinear function at texel centres fall between points); the
            // kink along n's horizon is what is left, and k = 32 against k = 64
            // bounds that error.
            auto irradiance = [&](uint32_t k) {
                const uint32_t nu = map->width * k, nv = map->height * k;
                double sum = 0;
                for (uint32_t j = 0; j < nv; ++j) {
                    const double v = (j + 0.5) / nv, theta = std::numbers::pi * v;
                    for (uint32_t i = 0; i < nu; ++i) {
                        const double u = (i + 0.5) / nu, phi = 2 * std::numbers::pi * u;
                        const glm::dvec3 d(std::sin(theta) * std::sin(phi), std::cos(theta),
                                           -std::sin(theta) * std::cos(phi));
                        const double cosine = glm::dot(n, d);
                        if (cosine <= 0) continue;
                        const double l =
                            scene::luminance(bilinearAt(*map, info, glm::vec2(float(u), float(v))));
                        sum += l * cosine * std::sin(theta);
                    }
                }
                return sum * 2 * std::numbers::pi * std::numbers::pi / (double(nu) * nv);
            };
            const double exact = irradiance(64);
            auto zScore = [&](const std::vector<EnvTestResult>& rs) {
                double sum = 0, sumSquares = 0;
                for (const auto& r : rs) {
                    const double cosine = glm::dot(n, glm::dvec3(r.direction));
                    // A sample of pdf 0 (rounded into a cell of probability 0) is
                    // skipped, as the renderer skips it.
                    const double f = cosine > 0 && r.pdf > 0
                                         ? scene::luminance(r.radiance) * cosine / r.pdf
                                         : 0.0;
                    sum += f;
                    sumSquares += f * f;
                }
                const double count = double(rs.size()), mean = sum / count;
                const double standardError =
                    std::sqrt((sumSquares / count - mean * mean) / (count - 1));
                return std::pair{(mean - exact) / standardError, standardError};
            };
            const auto [z, standardError] = zScore(results);
            ASSERT_GT(exact, 0.0);
            EXPECT_LT(std::abs(irradiance(32) - exact), 0.05 * standardError)
                << "the quadrature is not exact enough";
            EXPECT_LT(std::abs(z), critical)
                << "E " << exact << " standard error " << standardError;
            EXPECT_GT(std::abs(zScore(nearestResults).first), 10 * critical) << "the power check";
        }
    }
}

// A 2048x1024 sky: a smooth gradient with a 0.5 degree sun `ratio` times brighter.
image::Image skyWithSun(float ratio) {
    image::Image map(2048, 1024);
    const glm::vec3 sun = glm::normalize(glm::vec3(0.3f, 0.6f, -0.74f));
    const float cosSun = std::cos(glm::radians(0.25f));
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x) {
            const glm::vec3 d =
                shared::equirectDirection((x + 0.5f) / map.width, (y + 0.5f) / map.height);
            const float sky = d.y > 0 ? 0.3f + 0.7f * d.y : 0.05f;
            map.at(x, y) =
                glm::dot(d, sun) >= cosSun ? glm::vec3(ratio) : glm::vec3(0.4f, 0.6f, 1.0f) * sky;
        }
    return map;
}

// Texel-space chi-square: sampled cells against the integral over each of the
// bilinear luminance x sin(theta), computed here by the midpoint rule
// (independently of the table's closed form), summed over 32 x 32 blocks so
// that most cells are well populated.
void expectTexelsFollowLuminance(const image::Image& map,
                                 const std::vector<EnvTestResult>& results) {
    constexpr uint32_t BLOCK = 32;
    const uint32_t bw = map.width / BLOCK, bh = map.height / BLOCK;
    const auto info = infoFor(map);
    std::vector<double> expected(bw * bh, 0), observed(bw * bh, 0);
    double total = 0;
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x) {
            const double w = cellIntegral(map, info, x, y, 2);
            expected[(y / BLOCK) * bw + x / BLOCK] += w;
            total += w;
        }
    for (double& e : expected) e *= double(results.size()) / total;
    for (const auto& r : results)
        observed[(r.texel / map.width / BLOCK) * bw + (r.texel % map.width) / BLOCK] += 1;
    const auto chi = test::chiSquareTest(observed, expected);
    EXPECT_GT(chi.pValue, ALPHA) << "chi2 " << chi.statistic << " dof " << chi.degreesOfFreedom;
}

TEST(EnvironmentSampling, SkyWithSunAtExtremeRatios) {
    for (float ratio : {1e5f, 1e7f}) {
        SCOPED_TRACE(ratio);
        const image::Image map = skyWithSun(ratio);
        const auto table = scene::buildEnvironmentTable(map);
        // No cell has probability 0: the sky is positive everywhere (a float CDF fails this at
        // 1e7).
        for (size_t i = 0; i < map.pixels.size(); ++i)
            ASSERT_GT(table.entries[i].probability, 0.0f) << i;
        const auto results = sample(map, table, infoFor(map));
        expectPdfsAgree(results);
        expectTexelsFollowLuminance(map, results);
        EXPECT_NEAR(integrateInMapCoordinates(table, infoFor(map)), 1.0, 1e-3)
            << "pdf does not integrate to 1";
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
        const auto results = sample(map, table, infoFor(map), 8, /*largestUniforms*/ true);
        for (const auto& r : results) {
            ASSERT_LT(r.texel, map.width * map.height);
            ASSERT_TRUE(std::isfinite(r.direction.x) && std::isfinite(r.direction.y) &&
                        std::isfinite(r.direction.z));
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
    EXPECT_TRUE(scene::buildEnvironmentTable(image::Image(8, 4))
                    .entries.empty());  // black map: no sampling
}

}  // namespace
