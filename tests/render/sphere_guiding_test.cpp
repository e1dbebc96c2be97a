// Diffuse samples guided toward smooth specular spheres (--guide-spheres,
// shared/path_tracer.h sampleGuidedDiffuse): which spheres the host lists,
// that the samples follow the mixture density they report (chi-square
// against a density written here from first principles), and that a guided
// render estimates the same image as cosine sampling (block z-test). How much
// sooner it reaches an error is measured, not tested: docs/TRADEOFFS.md.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "image/statistics.h"
#include "reference/path_tracer_view.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "support/direction_chi2.h"
#include "support/test_context.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"
#include "wavefront/render_types.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

scene::Material material(scene::MaterialKind kind, float roughness = 0.0f) {
    scene::Material m;
    m.kind = kind;
    m.reflectance = glm::vec3(0.9f);
    m.roughness = roughness;
    return m;
}

// A diffuse floor (material 0) at y = 0 with a small emissive quad (material
// 1) above it, and spheres of the given materials appended by the caller.
scene::Scene floorWithLamp() {
    scene::Scene s;
    s.materials = {material(scene::MaterialKind::Diffuse), material(scene::MaterialKind::Diffuse)};
    s.materials[1].emission = glm::vec3(10.0f);
    scene::Mesh floor;
    floor.name = "floor";
    floor.positions = {{-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    floor.material = 0;
    scene::Mesh lamp = floor;
    lamp.name = "lamp";
    lamp.positions = {{-0.2f, 3, -0.2f}, {-0.2f, 3, 0.2f}, {0.2f, 3, 0.2f}, {0.2f, 3, -0.2f}};
    lamp.material = 1;
    s.meshes = {floor, lamp};
    return s;
}

uint32_t addSphere(scene::Scene& s, glm::vec3 center, float radius, scene::Material m) {
    s.materials.push_back(m);
    s.spheres.push_back({"sphere", center, radius, uint32_t(s.materials.size() - 1)});
    return uint32_t(s.spheres.size() - 1);
}

// Render space: the tables' coordinates.
glm::vec3 toRender(const wavefront::SceneTables& t, glm::vec3 world) {
    return glm::vec3(glm::dvec3(world) - t.worldOrigin);
}

// Mirrors, glass and smooth metals are listed, largest first; rough metal,
// diffuse spheres and glass of ior 1 are not; nothing is listed without an
// emissive surface (a constant sky and a point light only) or under an
// environment map (a constant sky beside the lamp keeps the list).
TEST(SphereGuiding, ListsTheSmoothSpecularSpheresWhereAnEmissiveSurfaceCanBeSeen) {
    scene::Scene s = floorWithLamp();
    addSphere(s, {0, 1, 0}, 0.3f, material(scene::MaterialKind::Mirror));
    addSphere(s, {1, 1, 0}, 0.5f, material(scene::MaterialKind::Dielectric));
    addSphere(s, {2, 1, 0}, 0.4f, material(scene::MaterialKind::Conductor, 0.0f));
    addSphere(s, {3, 1, 0}, 0.6f, material(scene::MaterialKind::Conductor, 0.5f));
    addSphere(s, {-1, 1, 0}, 0.7f, material(scene::MaterialKind::Diffuse));
    scene::Material airGlass = material(scene::MaterialKind::Dielectric);
    airGlass.ior = 1.0f;
    addSphere(s, {-2, 1, 0}, 0.8f, airGlass);
    const wavefront::SceneTables t = wavefront::buildSceneTables(s);
    ASSERT_EQ(t.guideSpheres.size(), 3u);
    EXPECT_EQ(t.guideSpheres[0], glm::vec4(toRender(t, {1, 1, 0}), 0.5f));
    EXPECT_EQ(t.guideSpheres[1], glm::vec4(toRender(t, {2, 1, 0}), 0.4f));
    EXPECT_EQ(t.guideSpheres[2], glm::vec4(toRender(t, {0, 1, 0}), 0.3f));

    wavefront::RenderSettings settings;
    EXPECT_EQ(wavefront::renderSceneInfo(t, settings).guideSphereCount, 3u);
    settings.guideFraction = 0.0f;
    const shared::SceneInfo off = wavefront::renderSceneInfo(t, settings);
    EXPECT_EQ(off.guideSphereCount, 0u);
    EXPECT_EQ(wavefront::renderFeatures(t, off) & VKP_FEATURE_SPHERE_GUIDING, 0u);

    scene::Scene dark = s;
    dark.materials[1].emission = glm::vec3(0.0f);
    dark.environment = scene::Environment{};
    dark.environment->color = glm::vec3(1.0f);
    dark.pointLights.push_back({});
    EXPECT_TRUE(wavefront::buildSceneTables(dark).guideSpheres.empty());
    scene::Scene sky = s;
    sky.environment = scene::Environment{};
    sky.environment->color = glm::vec3(1.0f);
    EXPECT_EQ(wavefront::buildSceneTables(sky).guideSpheres.size(), 3u);
    sky.environment->map = image::Image(4, 2);
    EXPECT_TRUE(wavefront::buildSceneTables(sky).guideSpheres.empty());

    scene::Scene many = floorWithLamp();
    for (int i = 0; i < 12; ++i)
        addSphere(many, {float(i), 2, 0}, 0.01f * float(i + 1),
                  material(scene::MaterialKind::Mirror));
    const wavefront::SceneTables m = wavefront::buildSceneTables(many);
    ASSERT_EQ(m.guideSpheres.size(), size_t(VKP_MAX_GUIDE_SPHERES));
    EXPECT_FLOAT_EQ(m.guideSpheres.back().w, 0.05f);  // the 8 largest: radii 0.12 down to 0.05
}

// The mixture's density written out here: (1 - a) cos / pi plus a / K times
// the uniform density of each candidate's cone that holds wi, in double.
struct Mixture {
    glm::dvec3 p, n;
    std::vector<glm::dvec4> cones;  // candidate spheres
    double fraction;

    double operator()(glm::vec3 w) const {
        const glm::dvec3 wi = glm::normalize(glm::dvec3(w));
        const double cosine = glm::dot(n, wi);
        if (cosine <= 0) return 0;  // f = 0 there: such samples are lost, not returned
        double cone = 0;
        for (const glm::dvec4& c : cones) {
            const glm::dvec3 d = glm::dvec3(c) - p;
            const double dist = glm::length(d), sinMax = c.w / dist;
            const double cosMax = std::sqrt(1 - sinMax * sinMax);
            if (glm::dot(wi, d / dist) >= cosMax) cone += 1 / (2 * std::numbers::pi * (1 - cosMax));
        }
        return (1 - fraction) * cosine / std::numbers::pi + fraction * cone / double(cones.size());
    }
};

// From a floor point: a mirror sphere, a smaller one inside its cone (the
// cones overlap), a glass sphere half below the horizon (some of its samples
// are lost), a sphere wholly below the floor and one the point is inside of
// (neither a candidate). The samples follow the density above (chi-square,
// lost samples their own cell), each reports it to 1e-4 and carries weight
// albedo cos / pdf.
TEST(SphereGuiding, SamplesFollowTheMixtureDensity) {
    scene::Scene s = floorWithLamp();
    const glm::vec3 point(0.1f, 0.0f, -0.2f);
    const std::vector<glm::vec4> candidates = {
        {0.6f, 0.6f, -0.2f, 0.3f}, {0.9f, 0.9f, 0.0f, 0.25f}, {-1.1f, 0.1f, 0.3f, 0.4f}};
    for (const glm::vec4& c : candidates)
        addSphere(s, glm::vec3(c), c.w, material(scene::MaterialKind::Mirror));
    addSphere(s, {0, -1, 2}, 0.5f, material(scene::MaterialKind::Dielectric));  // below the horizon
    addSphere(s, {0.1f, 0.2f, -0.2f}, 0.3f,
              material(scene::MaterialKind::Mirror));  // around the point
    const wavefront::SceneTables t = wavefront::buildSceneTables(s);
    wavefront::RenderSettings settings;
    settings.guideFraction = 0.4f;
    const shared::SceneInfo info = wavefront::renderSceneInfo(t, settings);
    ASSERT_EQ(info.guideSphereCount, 5u);
    const shared::PathTracerView view(t, info);

    shared::SurfacePoint surface{};
    surface.position = toRender(t, point);
    surface.normal = surface.shadingNormal = glm::vec3(0, 1, 0);
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f));
    const shared::Material floor = t.materials[0];
    const auto g = view.guideSpheresAt(floor, surface, wo);
    ASSERT_EQ(g.count, 3u);

    Mixture density{glm::dvec3(surface.position), glm::dvec3(0, 1, 0), {}, 0.4};
    for (const glm::vec4& c : candidates)
        density.cones.emplace_back(glm::dvec3(toRender(t, glm::vec3(c))), c.w);

    std::mt19937 rng(17);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const size_t samples = 1000000;
    std::vector<glm::vec3> valid;
    double worstPdf = 0, worstWeight = 0;
    for (size_t i = 0; i < samples; ++i) {
        const glm::vec2 u(uniform(rng), uniform(rng));
        const shared::BsdfSample b =
            view.sampleGuidedDiffuse(floor, surface, wo, g, u, uniform(rng));
        if (!b.valid) continue;
        valid.push_back(b.direction);
        const double expected = density(b.direction);
        worstPdf = std::max(worstPdf, std::abs(b.pdf / expected - 1));
        const double weight = 0.9 * b.direction.y / std::numbers::pi / expected;
        worstWeight = std::max(worstWeight, std::abs(b.weight.x / weight - 1));
    }
    EXPECT_LT(worstPdf, 1e-4);
    EXPECT_LT(worstWeight, 1e-4);
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(glm::vec3(0, 1, 0));
    const double integral = test::integrateOverSphere(grid, density);
    EXPECT_LT(integral, 1.0) << "the half-hidden sphere loses samples";
    EXPECT_NEAR(double(valid.size()) / samples, integral, 5e-3);
    const auto result =
        test::chiSquareDirectionsWithLosses(grid, valid, samples - valid.size(), density);
    EXPECT_GT(result.pValue, 0.01)
        << "chi2 " << result.statistic << ", dof " << result.degreesOfFreedom;

    // Power: the same samples against the cosine lobe alone are rejected.
    Mixture cosineOnly = density;
    cosineOnly.fraction = 0;
    EXPECT_LT(
        test::chiSquareDirectionsWithLosses(grid, valid, samples - valid.size(), cosineOnly).pValue,
        1e-10);
}

// A white furnace that guides: a white diffuse sphere between a mirror and a
// clear glass sphere (nothing absorbs) inside a black box whose inner faces
// emit 1. Every pixel's expected value is then 1 exactly (depth 64 leaves
// less than 1e-6 of paths unfinished here), and light samples of the box's
// triangles are weighed against the guided mixture; a guided render on
// either device must not differ from an image of ones by more than its noise
// (block z-test, 1% family-wise: critical |z| 3.53 over 24 blocks; measured
// worst |z| 1.12 on both). A mixture density off by a quarter for the cone
// samples (one sphere too many in its denominator) fails it at |z| 5.4.
TEST(SphereGuiding, WhiteFurnaceStaysWhite) {
    scene::Scene s;
    scene::Material wall = material(scene::MaterialKind::Diffuse);
    wall.reflectance = glm::vec3(0.0f);
    wall.emission = glm::vec3(1.0f);
    s.materials = {wall};
    // The cube [-6, 6]^3, each face two triangles wound so that their normal
    // (p1 - p0) x (p2 - p0) points inward: triangles emit from that side.
    scene::Mesh box;
    box.name = "box";
    const float h = 6.0f;
    for (int axis = 0; axis < 3; ++axis)
        for (const float side : {-1.0f, 1.0f}) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            auto corner = [&](float a, float b) {
                glm::vec3 p(0.0f);
                p[axis] = side * h;
                p[u] = a * h;
                p[v] = b * h;
                return p;
            };
            const uint32_t first = uint32_t(box.positions.size());
            box.positions.insert(box.positions.end(),
                                 {corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1)});
            // (u x v) = +axis: counter-clockwise in (u, v) faces +axis, inward on the -axis face.
            if (side < 0)
                box.triangles.insert(box.triangles.end(), {{first, first + 1, first + 2},
                                                           {first, first + 2, first + 3}});
            else
                box.triangles.insert(box.triangles.end(), {{first, first + 2, first + 1},
                                                           {first, first + 3, first + 2}});
        }
    box.material = 0;
    s.meshes.push_back(box);
    addSphere(s, {0.0f, 0.0f, 0.0f}, 1.0f, material(scene::MaterialKind::Diffuse));
    s.materials.back().reflectance = glm::vec3(1.0f);
    addSphere(s, {2.5f, 0.0f, 0.0f}, 1.0f, material(scene::MaterialKind::Mirror));
    s.materials.back().reflectance = glm::vec3(1.0f);
    addSphere(s, {-2.5f, 0.0f, 0.0f}, 1.0f, material(scene::MaterialKind::Dielectric));
    s.materials.back().reflectance = glm::vec3(1.0f);
    s.camera.position = {0.0f, 0.0f, 5.5f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.xfovDegrees = 50.0f;
    wavefront::RenderSettings settings;
    settings.width = 48;
    settings.height = 32;
    settings.samplesPerPixel = 64;
    settings.maxDepth = 64;
    const wavefront::SceneTables t = wavefront::buildSceneTables(s);
    ASSERT_EQ(t.guideSpheres.size(), 2u);
    image::Image ones(settings.width, settings.height), exact(settings.width, settings.height);
    for (glm::vec3& p : ones.pixels) p = glm::vec3(1.0f);
    // Lossless bounces still round: each multiplies the throughput by 1 to
    // within an ulp, so pixels that see only glass and mirror come out a few
    // ulps off 1 with a variance near 1e-17. The exact side's variance of
    // (1e-5)^2 covers 64 bounces of such rounding and no sampling bias.
    for (glm::vec3& p : exact.pixels) p = glm::vec3(1e-10f);
    for (const bool gpu : {false, true}) {
        SCOPED_TRACE(gpu ? "GPU" : "CPU reference");
        const wavefront::RenderResult r =
            gpu ? wavefront::GpuRenderer(test::context(), s, settings).render()
                : reference::ReferenceRenderer(s, settings).render();
        const image::BlockComparison z =
            image::compareBlocks(r.image, r.varianceOfMean, ones, exact, 8, 0.01);
        EXPECT_EQ(z.rejected, 0u) << "worst |z| " << z.worstZ << " at " << z.worstX << ","
                                  << z.worstY;
    }
}

// CBspheres, the CPU reference at 64x48, 256 spp, depth 4, guided (the
// default) and not, with different seeds: no 8x8 block of the two differs
// beyond the z-test's 1% family-wise false-alarm rate (Sidak-corrected
// critical |z| 3.71 over 48 blocks). The caustics that guiding finds sooner
// are in the cosine-sampled image too, only noisier. Measured over 3 seed
// pairs (3/4, 5/6, 7/8): worst |z| 2.18, 2.97, 1.96.
TEST(SphereGuiding, EstimatesTheSameImageAsCosineSampling) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = scene::loadScene(test::sharedScene("CBspheres.dae").string());
    wavefront::RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samplesPerPixel = 256;
    settings.maxDepth = 4;
    settings.seed = 3;
    const auto guided = reference::ReferenceRenderer(s, settings).render();
    settings.guideFraction = 0.0f;
    settings.seed = 4;
    const auto cosine = reference::ReferenceRenderer(s, settings).render();
    const image::BlockComparison z = image::compareBlocks(
        guided.image, guided.varianceOfMean, cosine.image, cosine.varianceOfMean, 8, 0.01);
    EXPECT_EQ(z.rejected, 0u) << "worst |z| " << z.worstZ;
}

}  // namespace
