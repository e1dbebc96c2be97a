// Alpha coverage (glTF alphaMode; shaders/shared/alpha.h, the traversal's
// alpha test in shared/bvh_traverse.h and path_tracer.h): planes whose answer
// is known exactly. A black plane in front of a white sky (a furnace of
// radiance 1) shows 1 where a camera ray passes through it and 0 where it
// meets it, so each pixel estimates the transmitted fraction: MASK with a
// constant alpha or an alpha checker gives exactly 0 or 1, BLEND with alpha a
// gives 1 - a with Bernoulli noise a (1 - a) per sample. Shadow rays through
// a BLEND plane under a directional light darken by exactly 1 - a, and with
// an area light (light samples and BSDF samples joined by MIS) likewise.
// Statistical bounds are 5 standard errors measured by the render's own
// variance AOV (a false alarm of 6e-7 per check, as tests/render/render_test.cpp).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "image/statistics.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "support/gpu_render.h"
#include "support/pixel_match.h"
#include "support/test_context.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

constexpr double PI = 3.14159265358979323846;
constexpr double Z_BOUND = 5.0;
constexpr uint32_t FILM = 64;  // pixels a side

using scene::AlphaMode;

// A quad with corners c, c + down, c + down + right, c + right; texture
// coordinates (0, 0) at c, u along `right`, v along `down` (glTF: v runs
// down the image); it faces cross(down, right).
scene::Mesh quad(glm::vec3 c, glm::vec3 down, glm::vec3 right, uint32_t material) {
    scene::Mesh m;
    m.positions = {c, c + down, c + down + right, c + right};
    m.texcoords0 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.material = material;
    return m;
}

// The square [-h, h]^2 of the plane z = 0, facing +z, the image upright.
scene::Mesh square(float h, uint32_t material) {
    return quad({-h, h, 0}, {0, -2 * h, 0}, {2 * h, 0, 0}, material);
}

scene::Material black(AlphaMode mode, float alpha, float cutoff = 0.5f) {
    scene::Material m;
    m.reflectance = glm::vec3(0.0f);
    m.alphaMode = mode;
    m.alpha = alpha;
    m.alphaCutoff = cutoff;
    return m;
}

// The furnace: `plane` on a square of half-size h at z = 0, seen from
// (0, 0, 2) with a horizontal field of view of 2 atan(1/2), so the film sees
// exactly [-1, 1]^2 of it (texture_test's framing), under a white sky.
scene::Scene furnace(const scene::Material& plane, float h = 1.5f) {
    scene::Scene s;
    s.materials.push_back(plane);
    s.meshes.push_back(square(h, 0));
    s.camera.position = {0, 0, 2};
    s.camera.target = {0, 0, 0};
    s.camera.xfovDegrees = float(2 * std::atan(0.5) * 180 / PI);
    scene::Environment env;
    env.color = glm::vec3(1.0f);
    s.environment = env;
    return s;
}

// Material `material`'s base-colour texture: an image whose alpha is a
// checker of `cells` x `cells` texels, texel (i, j) of alpha a0 where i + j is
// even, a1 where odd (RGB black), read nearest.
scene::Scene withAlphaChecker(scene::Scene s, int cells, double a0, double a1,
                              uint32_t material = 0) {
    scene::TextureImage image;
    image.name = "checker";
    image.width = image.height = uint32_t(cells);
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const double a = (i + j) % 2 == 0 ? a0 : a1;
            image.texels.push_back(glm::u16vec4(0, 0, 0, uint16_t(std::lround(a * 65535))));
        }
    s.images.push_back(image);
    s.textures.push_back(
        {0, scene::TextureWrap::Repeat, scene::TextureWrap::Repeat, /*nearest*/ true});
    s.materials.at(material).baseColorTexture.texture = 0;
    return s;
}

wavefront::RenderSettings settings(uint32_t spp, uint32_t maxDepth = 4, uint32_t seed = 1) {
    wavefront::RenderSettings s;
    s.width = s.height = FILM;
    s.samplesPerPixel = spp;
    s.maxDepth = maxDepth;
    s.seed = seed;
    return s;
}

using test::renderGpu;

image::RegionMean meanOf(
    const wavefront::RenderResult& r, const std::function<bool(uint32_t, uint32_t)>& select =
                                          [](uint32_t, uint32_t) { return true; }) {
    const image::RegionMean m = image::regionMean(r.image, r.varianceOfMean, select);
    EXPECT_GT(m.pixels, 0u);
    return m;
}

// |mean - expected| in standard errors.
double zScore(const image::RegionMean& m, double expected) {
    return std::abs(m.mean - expected) / m.standardError;
}

void expectEveryPixel(const wavefront::RenderResult& r, float expected, float tolerance,
                      const char* what) {
    for (size_t i = 0; i < r.image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(r.image.pixels[i][c], expected, tolerance) << what << ", pixel " << i;
}

// ---- furnace: what the camera sees through the plane ------------------------------

// BLEND: each camera ray passes with probability 1 - alpha. The mean over the
// film (4096 pixels x 64 spp) must be 1 - alpha within 5 standard errors
// (~0.01 at alpha 0.5), and the per-sample variance the AOV measures must be
// the Bernoulli variance alpha (1 - alpha) (within 5 standard errors of its
// mean over the pixels, ~0.3% of it): decisions independent from sample to
// sample, not fixed per pixel (variance 0) or shared by a pixel's samples.
// Power: the same image is rejected as an estimate of 1 - (alpha + 0.05).
TEST(AlphaFurnace, BlendPlaneTransmitsOneMinusAlpha) {
    for (float alpha : {0.25f, 0.5f, 0.9f}) {
        SCOPED_TRACE(alpha);
        const auto r = renderGpu(furnace(black(AlphaMode::Blend, alpha)), settings(64));
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        const image::RegionMean m = meanOf(r);
        EXPECT_LE(zScore(m, 1.0 - alpha), Z_BOUND)
            << "mean " << m.mean << ", standard error " << m.standardError;
        EXPECT_GT(zScore(m, 1.0 - (alpha + 0.05)), Z_BOUND)
            << "the test cannot tell 0.05 of alpha apart";

        // Per-sample variance, pixel by pixel: n * variance of the mean.
        double sum = 0, sumSquares = 0;
        for (const glm::vec3& v : r.varianceOfMean.pixels) {
            const double s2 = double(v.x) * r.samplesPerPixel;
            sum += s2;
            sumSquares += s2 * s2;
        }
        const double n = double(r.varianceOfMean.pixels.size());
        const double mean = sum / n,
                     standardError = std::sqrt((sumSquares / n - mean * mean) / (n - 1));
        EXPECT_NEAR(mean, alpha * (1.0 - alpha), Z_BOUND * standardError) << "per-sample variance";
        RecordProperty(
            fmt::format("alpha{}", alpha),
            fmt::format("mean {} z {:.2f}; variance {} z {:.2f}", m.mean, zScore(m, 1.0 - alpha),
                        mean, (mean - alpha * (1.0 - alpha)) / standardError));
    }
}

// Alpha 0 never covers (u < alpha, u in [0, 1)) and alpha 1 everywhere is
// opaque: exactly the sky and exactly black, no noise.
TEST(AlphaFurnace, BlendAlphaZeroAndOneAreExact) {
    expectEveryPixel(renderGpu(furnace(black(AlphaMode::Blend, 0.0f)), settings(4)), 1.0f, 0.0f,
                     "alpha 0");
    expectEveryPixel(renderGpu(furnace(black(AlphaMode::Blend, 1.0f)), settings(4)), 0.0f, 0.0f,
                     "alpha 1");
}

// MASK with a constant alpha 0.5: a cutoff below it keeps the whole plane
// (exactly black), one above it removes it (exactly the sky), on the GPU and
// the CPU.
TEST(AlphaFurnace, MaskCutoffAboveOrBelowTheAlpha) {
    for (bool cpu : {false, true}) {
        SCOPED_TRACE(cpu ? "CPU reference" : "GPU");
        auto render = [&](float cutoff) {
            const scene::Scene s = furnace(black(AlphaMode::Mask, 0.5f, cutoff));
            return cpu ? reference::ReferenceRenderer(s, settings(2)).render()
                       : renderGpu(s, settings(2));
        };
        expectEveryPixel(render(0.4f), 0.0f, 0.0f, "cutoff 0.4: opaque");
        expectEveryPixel(render(0.5f), 0.0f, 0.0f, "cutoff 0.5: alpha >= cutoff is opaque");
        expectEveryPixel(render(0.6f), 1.0f, 0.0f, "cutoff 0.6: a hole");
    }
}

// An 8 x 8 alpha checker (nearest) on the square that exactly fills the
// 64 x 64 film: each texel covers 8 x 8 pixels, and every pixel whose
// footprint lies inside one texel sees only it. MASK (alpha 0 and 1, cutoff
// 0.5): exactly the sky in the holes, exactly black elsewhere. BLEND (alpha
// 0.25 and 0.75): each kind of texel transmits its own 1 - alpha, within 5
// standard errors.
TEST(AlphaFurnace, CheckerTextureAlpha) {
    auto texelOf = [](uint32_t x, uint32_t y) { return glm::ivec2(x / 8, y / 8); };
    auto inside = [](uint32_t x, uint32_t y) {
        return x % 8 != 0 && x % 8 != 7 && y % 8 != 0 && y % 8 != 7;
    };
    {
        const auto r =
            renderGpu(withAlphaChecker(furnace(black(AlphaMode::Mask, 1.0f), 1.0f), 8, 0.0, 1.0),
                      settings(4));
        int holes = 0, solid = 0;
        for (uint32_t y = 0; y < FILM; ++y)
            for (uint32_t x = 0; x < FILM; ++x) {
                if (!inside(x, y)) continue;
                const glm::ivec2 t = texelOf(x, y);
                const bool hole = (t.x + t.y) % 2 == 0;
                ASSERT_EQ(r.image.at(x, y).x, hole ? 1.0f : 0.0f) << x << "," << y;
                (hole ? holes : solid)++;
            }
        EXPECT_EQ(holes, 32 * 36);
        EXPECT_EQ(solid, 32 * 36);
    }
    {
        const auto r =
            renderGpu(withAlphaChecker(furnace(black(AlphaMode::Blend, 1.0f), 1.0f), 8, 0.25, 0.75),
                      settings(64));
        for (const int parity : {0, 1}) {
            const image::RegionMean m = meanOf(r, [&](uint32_t x, uint32_t y) {
                const glm::ivec2 t = texelOf(x, y);
                return inside(x, y) && (t.x + t.y) % 2 == parity;
            });
            const double expected = parity == 0 ? 0.75 : 0.25;
            EXPECT_LE(zScore(m, expected), Z_BOUND)
                << "texels of parity " << parity << ": mean " << m.mean;
            RecordProperty(fmt::format("parity{}", parity),
                           fmt::format("z {:.2f}", zScore(m, expected)));
        }
    }
}

// The alpha is the product of baseColorFactor's (0.8), the texture's (0.5, a
// 1 x 1 image) and COLOR_0's (0.5 at every vertex): 0.2. BLEND transmits 0.8;
// MASK with cutoff 0.25 is a hole, with cutoff 0.15 opaque.
TEST(AlphaFurnace, AlphaIsFactorTimesTextureTimesVertexColour) {
    auto plane = [](AlphaMode mode, float cutoff) {
        scene::Scene s = withAlphaChecker(furnace(black(mode, 0.8f, cutoff)), 1, 0.5, 0.5);
        s.meshes[0].colors.assign(4, glm::vec4(1.0f, 1.0f, 1.0f, 0.5f));
        return s;
    };
    const image::RegionMean m = meanOf(renderGpu(plane(AlphaMode::Blend, 0.5f), settings(64)));
    EXPECT_LE(zScore(m, 0.8), Z_BOUND) << "mean " << m.mean;
    RecordProperty("z", fmt::format("{:.2f}", zScore(m, 0.8)));
    expectEveryPixel(renderGpu(plane(AlphaMode::Mask, 0.25f), settings(2)), 1.0f, 0.0f,
                     "cutoff 0.25");
    expectEveryPixel(renderGpu(plane(AlphaMode::Mask, 0.15f), settings(2)), 0.0f, 0.0f,
                     "cutoff 0.15");
}

// Spheres have no texture coordinates and are opaque whatever their
// material's alphaMode (the importer warns): a black BLEND sphere in the
// furnace is black.
TEST(AlphaFurnace, SpheresStayOpaque) {
    scene::Scene s = furnace(black(AlphaMode::Blend, 0.5f));
    s.meshes.clear();
    s.spheres.push_back({"ball", glm::vec3(0.0f), 3.0f,
                         0});  // the camera at distance 2 is inside: every ray meets it
    expectEveryPixel(renderGpu(s, settings(2)), 0.0f, 0.0f, "a BLEND sphere");
}

// ---- shadows and light through a BLEND plane ----------------------------------------

// The ground y = 0 (albedo 0.5), a plane at y = 1 over all of it, and the
// camera between them at y = 0.5 looking down (60 degrees: it sees the ground
// within 0.3 of the origin, and never the plane). No sky.
scene::Scene groundUnderPlane(const scene::Material& plane) {
    scene::Scene s;
    scene::Material ground;
    ground.reflectance = glm::vec3(0.5f);
    s.materials = {ground, plane};
    s.meshes.push_back(quad({-10, 0, -10}, {0, 0, 20}, {20, 0, 0}, 0));  // faces +y
    s.meshes.push_back(quad({-10, 1, -10}, {0, 0, 20}, {20, 0, 0}, 1));
    s.camera.position = {0.0f, 0.5f, 0.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.up = {0.0f, 0.0f, -1.0f};
    s.camera.xfovDegrees = 60.0f;
    return s;
}

// A directional light straight down (irradiance 1): the ground reflects
// rho / pi where the shadow ray passes and 0 where the plane stops it, so the
// image is rho / pi x (1 - alpha): exactly rho / pi at alpha 0, exactly 0 at
// alpha 1 (depth 1: direct light only, which is all there is).
TEST(AlphaShadows, DirectionalLightThroughABlendPlaneDarkensByAlpha) {
    const double lit = 0.5 / PI;
    for (float alpha : {0.0f, 0.3f, 0.5f, 1.0f}) {
        SCOPED_TRACE(alpha);
        scene::Scene s = groundUnderPlane(black(AlphaMode::Blend, alpha));
        s.directionalLights.push_back({glm::vec3(0, -1, 0), glm::vec3(1.0f)});
        const auto r = renderGpu(s, settings(64, 1));
        if (alpha == 0.0f || alpha == 1.0f) {
            expectEveryPixel(r, float(lit * (1.0 - alpha)), 1e-6f, "no noise");
            continue;
        }
        const image::RegionMean m = meanOf(r);
        EXPECT_LE(zScore(m, lit * (1.0 - alpha)), Z_BOUND)
            << "mean " << m.mean << " of " << lit * (1 - alpha);
        RecordProperty(fmt::format("alpha{}", alpha),
                       fmt::format("z {:.2f}", zScore(m, lit * (1.0 - alpha))));
    }
}

// An emitter (a 1 x 1 quad at y = 2 facing down, radiance 10) lights the
// ground through the plane: light samples (shadow rays) and BSDF samples
// (closest-hit rays that must pass the plane to reach the emitter), joined by
// MIS, each see it with probability 1 - alpha, so the image is (1 - alpha)
// times the image without the plane. Two renders with different seeds: z of
// mean_with - (1 - alpha) mean_without against both standard errors.
TEST(AlphaShadows, AreaLightThroughABlendPlaneWithMis) {
    const float alpha = 0.4f;
    scene::Scene s = groundUnderPlane(black(AlphaMode::Blend, alpha));
    scene::Material lamp;
    lamp.reflectance = glm::vec3(0.0f);
    lamp.emission = glm::vec3(10.0f);
    s.materials.push_back(lamp);
    s.meshes.push_back(quad({-0.5f, 2, -0.5f}, {1, 0, 0}, {0, 0, 1}, 2));  // faces -y
    const image::RegionMean with = meanOf(renderGpu(s, settings(64, 1, 1)));
    s.meshes.erase(s.meshes.begin() + 1);  // no plane
    const image::RegionMean without = meanOf(renderGpu(s, settings(64, 1, 2)));
    ASSERT_GT(without.mean, 0.1);
    const double z = (with.mean - (1 - alpha) * without.mean) /
                     std::hypot(with.standardError, (1 - alpha) * without.standardError);
    EXPECT_LE(std::abs(z), Z_BOUND) << "with " << with.mean << ", without " << without.mean;
    RecordProperty("z", fmt::format("{:.2f} (with {}, without {})", z, with.mean, without.mean));
}

// An emitter with holes is not light-sampled (a light sample could land in a
// hole): the BLEND emitter of alpha 0.5 is not in the light list, found by
// BSDF samples alone, and lights the ground half as much as the same emitter
// opaque (which is light-sampled).
TEST(AlphaShadows, EmitterWithHolesLightsByItsAlpha) {
    scene::Scene s = groundUnderPlane(black(AlphaMode::Blend, 0.0f));
    s.meshes.erase(s.meshes.begin() + 1);
    scene::Material lamp = black(AlphaMode::Blend, 0.5f);
    lamp.emission = glm::vec3(10.0f);
    s.materials.push_back(lamp);
    s.meshes.push_back(quad({-0.5f, 2, -0.5f}, {1, 0, 0}, {0, 0, 1}, 2));
    EXPECT_TRUE(wavefront::buildSceneTables(s).lights.empty());
    const image::RegionMean holes = meanOf(renderGpu(s, settings(64, 1, 1)));
    s.materials[2].alphaMode = AlphaMode::Opaque;
    EXPECT_EQ(wavefront::buildSceneTables(s).lights.size(), 2u);  // its two triangles
    const image::RegionMean solid = meanOf(renderGpu(s, settings(64, 1, 2)));
    const double z = (holes.mean - 0.5 * solid.mean) /
                     std::hypot(holes.standardError, 0.5 * solid.standardError);
    EXPECT_LE(std::abs(z), Z_BOUND) << "with holes " << holes.mean << ", solid " << solid.mean;
    RecordProperty("z", fmt::format("{:.2f} (holes {}, solid {})", z, holes.mean, solid.mean));
}

// ---- one scene, every renderer ------------------------------------------------------

// Both modes, a textured and vertex-coloured BLEND plane, shadows from an
// area and a directional light, and a MASK card in front of the camera.
scene::Scene everything() {
    scene::Scene s =
        withAlphaChecker(groundUnderPlane(black(AlphaMode::Blend, 0.9f)), 4, 0.3, 0.8, 1);
    s.materials[1].reflectance = glm::vec3(0.6f, 0.5f, 0.4f);
    s.meshes[1].colors = {{1, 1, 1, 1}, {1, 1, 1, 0.5f}, {1, 1, 1, 1}, {1, 1, 1, 0.2f}};
    scene::Material lamp;
    lamp.emission = glm::vec3(4.0f);
    s.materials.push_back(lamp);
    s.meshes.push_back(quad({-0.5f, 2, -0.5f}, {1, 0, 0}, {0, 0, 1}, 2));
    s.materials.push_back(black(AlphaMode::Mask, 0.3f, 0.5f));  // a hole everywhere
    s.meshes.push_back(quad({-0.09f, 0.3f, -0.05f}, {0.06f, 0, 0}, {0, 0, 0.06f}, 3));
    s.materials.push_back(black(AlphaMode::Mask, 0.6f, 0.5f));  // solid
    s.meshes.push_back(quad({0.03f, 0.3f, 0.03f}, {0.06f, 0, 0}, {0, 0, 0.06f}, 4));
    s.directionalLights.push_back({glm::normalize(glm::vec3(0.3f, -1, 0.2f)), glm::vec3(2.0f)});
    return s;
}

bool sameBits(const image::Image& a, const image::Image& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

// The alpha test is a feature bit: scenes without MASK or BLEND triangles
// lack it (their kernels are the ones of before), scenes with them have it,
// and specialised or general, megakernel or wavefront, the image is the same
// bit for bit (the decisions hash the path, not the traversal order).
TEST(AlphaKernels, EveryKernelGivesTheSameImage) {
    const scene::Scene s = everything();
    wavefront::RenderSettings base = settings(2, 5);
    base.width = 32;
    base.height = 24;
    base.lightSamples = 2;
    base.kernel = wavefront::KernelForm::Wavefront;
    wavefront::GpuRenderer reference(test::context(), s, base);
    EXPECT_NE(reference.features() & VKP_FEATURE_ALPHA, 0u);
    const auto expected = reference.render();
    for (const auto form : {wavefront::KernelForm::Wavefront, wavefront::KernelForm::Megakernel})
        for (const bool specialize : {true, false}) {
            if (form == wavefront::KernelForm::Wavefront && specialize) continue;
            SCOPED_TRACE(std::string(wavefront::kernelFormName(form)) +
                         (specialize ? " specialised" : " general"));
            wavefront::RenderSettings other = base;
            other.kernel = form;
            other.specialize = specialize;
            const auto r = renderGpu(s, other);
            EXPECT_TRUE(sameBits(r.image, expected.image));
            EXPECT_TRUE(sameBits(r.varianceOfMean, expected.varianceOfMean));
            EXPECT_EQ(r.rays.closest, expected.rays.closest);
            EXPECT_EQ(r.rays.shadow, expected.rays.shadow);
        }

    scene::Scene opaque = s;
    for (scene::Material& m : opaque.materials) m.alphaMode = AlphaMode::Opaque;
    const wavefront::SceneTables tables = wavefront::buildSceneTables(opaque);
    EXPECT_EQ(wavefront::sceneFeatures(tables) & VKP_FEATURE_ALPHA, 0u);
    EXPECT_TRUE(tables.materialAlpha.empty()) << "no memory for alpha without it";
    EXPECT_EQ(tables.info.alphaTested, 0u);
}

// A material whose alpha cannot leave a hole anywhere is opaque to the
// renderer: MASK with alpha >= cutoff, BLEND with alpha 1, and an image
// whose alpha is 1 everywhere (an RGB picture), unless a mesh's COLOR_0
// lowers it.
TEST(AlphaKernels, MaterialsThatCannotLeaveAHoleAreOpaque) {
    auto tested = [](const scene::Scene& s) {
        const wavefront::SceneTables t = wavefront::buildSceneTables(s);
        EXPECT_EQ(t.materialAlpha.empty(), t.info.alphaTested == 0u);
        return (wavefront::sceneFeatures(t) & VKP_FEATURE_ALPHA) != 0;
    };
    EXPECT_FALSE(tested(furnace(black(AlphaMode::Mask, 0.7f, 0.5f))));
    EXPECT_FALSE(tested(furnace(black(AlphaMode::Blend, 1.0f))));
    EXPECT_FALSE(tested(withAlphaChecker(furnace(black(AlphaMode::Blend, 1.0f)), 2, 1.0, 1.0)));
    EXPECT_TRUE(tested(withAlphaChecker(furnace(black(AlphaMode::Blend, 1.0f)), 2, 1.0, 0.99)));
    EXPECT_TRUE(tested(furnace(black(AlphaMode::Mask, 0.4f, 0.5f))));
    scene::Scene coloured = furnace(black(AlphaMode::Blend, 1.0f));
    coloured.meshes[0].colors = {{1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1, 0.5f}, {1, 1, 1, 1}};
    EXPECT_TRUE(tested(coloured));
}

using test::matchingPixelFraction;

// The CPU reference decides every candidate as the GPU does (the same hash
// of the same path): with the same seed at least 97% of the pixels are equal,
// SameSeed's bound for paths that only rounding may send elsewhere; another
// seed's CPU image is not.
TEST(AlphaKernels, CpuReferenceMakesTheSameDecisions) {
    const scene::Scene s = everything();
    wavefront::RenderSettings base = settings(4, 5, 7);
    base.width = 48;
    base.height = 36;
    const auto gpu = renderGpu(s, base);
    const auto cpu = reference::ReferenceRenderer(s, base).render();
    const double matching = matchingPixelFraction(cpu.image, gpu.image);
    EXPECT_GE(matching, 0.97);
    base.seed = 8;
    const auto other = reference::ReferenceRenderer(s, base).render();
    const double otherMatching = matchingPixelFraction(other.image, gpu.image);
    EXPECT_LT(otherMatching, 0.97);
    RecordProperty("matching",
                   fmt::format("same seed {:.4f}, another seed {:.4f}", matching, otherMatching));
}

// A real model: the glTF sample ClearCoatTest (Debian's assimp-testmodels)
// has one BLEND material whose base-colour texture's alpha is a set of
// stripes: its scene tests alpha, and it renders without a NaN.
TEST(AlphaModels, ClearCoatTestHasAlphaStripes) {
    const std::filesystem::path file =
        "/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf";
    if (!std::filesystem::exists(file))
        GTEST_SKIP() << file << " is not installed (assimp-testmodels)";
    const scene::Scene s = scene::loadScene(file);
    const wavefront::SceneTables t = wavefront::buildSceneTables(s);
    EXPECT_EQ(t.info.alphaTested, 1u);
    EXPECT_NE(wavefront::sceneFeatures(t) & VKP_FEATURE_ALPHA, 0u);
    wavefront::RenderSettings small = settings(1, 3);
    small.width = 40;
    small.height = 30;
    EXPECT_EQ(renderGpu(s, small).nonFiniteSamples, 0u);
}

}  // namespace
