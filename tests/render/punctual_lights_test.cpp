// Point, spot and directional lights against their analytic radiance: a
// diffuse plane of albedo rho seen from above, lit by one delta light, has
// outgoing radiance rho / pi x E, with E the irradiance the light gives it:
// I cos(theta) / d^2 for a point light (times the spot's falloff), E cos(theta)
// for a directional one. Nothing else lights the plane or is seen (the sky is
// black, the plane cannot see itself), so each camera ray's estimate is
// exact: a pixel is the average of that radiance over its footprint, which
// the test integrates in double over the same camera rays (64 x 64 stratified
// jitters). Bound per pixel: 5 standard errors from the variance AOV (the
// jitter's noise) plus 1e-5 of the image's peak (float rounding along the
// path, ~1e-6 relative, with room; and at the spot's outer edge a pixel's
// footprint is lit over a sliver only, most of its 64 samples are 0, and
// the sample variance, 0 when all are, says little about its error:
// measured there, expected up to 2.3e-6 of the peak, rendered 0 or 1.6e-7).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "scene/camera.h"
#include "shared/camera.h"
#include "support/test_context.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

constexpr double PI = 3.14159265358979323846;
constexpr float ALBEDO = 0.5f;
constexpr uint32_t SIZE = 24;

// The plane y = 0, [-4, 4]^2, normal +y, seen straight down from y = 3.
scene::Scene litPlane() {
    scene::Scene s;
    scene::Material grey;
    grey.reflectance = glm::vec3(ALBEDO);
    s.materials.push_back(grey);
    scene::Mesh plane;
    plane.positions = {{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}};
    plane.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.meshes.push_back(plane);
    s.camera.position = {0.2f, 3.0f, 0.1f};
    s.camera.target = {0.2f, 0.0f, 0.1f};
    s.camera.up = {0.0f, 0.0f, -1.0f};
    s.camera.xfovDegrees = 60.0f;
    return s;
}

// Per channel, the pixel's expected value: the mean over its footprint of
// radiance(hit point), the hit point of each jittered camera ray with y = 0.
std::vector<glm::dvec3> expectedImage(const scene::Scene& s,
                                      const std::function<glm::dvec3(glm::dvec3)>& radiance) {
    const shared::Camera camera = scene::makeGpuCamera(s.camera, SIZE, SIZE);
    constexpr int K = 64;
    std::vector<glm::dvec3> image(SIZE * SIZE, glm::dvec3(0));
    for (uint32_t y = 0; y < SIZE; ++y)
        for (uint32_t x = 0; x < SIZE; ++x) {
            glm::dvec3 sum(0);
            for (int i = 0; i < K; ++i)
                for (int j = 0; j < K; ++j) {
                    const shared::Ray ray = shared::generateCameraRay(
                        camera, glm::uvec2(x, y), glm::vec2((i + 0.5f) / K, (j + 0.5f) / K));
                    const glm::dvec3 o(s.camera.position),
                        d = glm::normalize(glm::dvec3(ray.direction));
                    sum += radiance(o - o.y / d.y * d);
                }
            image[y * SIZE + x] = sum / double(K * K);
        }
    return image;
}

void expectMatches(const scene::Scene& s, const std::function<glm::dvec3(glm::dvec3)>& radiance) {
    wavefront::RenderSettings settings;
    settings.width = settings.height = SIZE;
    settings.samplesPerPixel = 64;
    settings.maxDepth = 4;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    const auto r = renderer.render();
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    const auto expected = expectedImage(s, radiance);
    double peak = 0;
    for (const glm::dvec3& e : expected) peak = std::max({peak, e.x, e.y, e.z});
    int bad = 0, lit = 0;
    double worst = 0;
    for (size_t i = 0; i < expected.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double e = expected[i][c], got = r.image.pixels[i][c];
            const double bound = 5 * std::sqrt(double(r.varianceOfMean.pixels[i][c])) + 1e-5 * peak;
            worst = std::max(worst, std::abs(got - e) / bound);
            bad += std::abs(got - e) > bound;
            lit += e > 0;
        }
    EXPECT_EQ(bad, 0) << "worst |error| / bound " << worst;
    EXPECT_GT(lit, 0);
}

TEST(PunctualLights, PointLightGivesIntensityCosineOverDistanceSquared) {
    scene::Scene s = litPlane();
    const glm::dvec3 position(0.3, 1.0, 0.2), intensity(2.0, 1.0, 0.5);
    s.pointLights.push_back({glm::vec3(position), glm::vec3(intensity)});
    expectMatches(s, [&](glm::dvec3 x) {
        const glm::dvec3 toLight = position - x;
        const double d2 = glm::dot(toLight, toLight), cosTheta = toLight.y / std::sqrt(d2);
        return ALBEDO / PI * intensity * cosTheta / d2;
    });
}

TEST(PunctualLights, DirectionalLightGivesIrradianceTimesCosine) {
    scene::Scene s = litPlane();
    const glm::dvec3 direction = glm::normalize(glm::dvec3(0.3, -1.0, 0.2)),
                     irradiance(1.0, 2.0, 3.0);
    s.directionalLights.push_back({glm::vec3(direction), glm::vec3(irradiance)});
    expectMatches(s, [&](glm::dvec3) { return ALBEDO / PI * irradiance * -direction.y; });
}

// The spot's falloff between its cones is glTF's (KHR_lights_punctual):
// t^2, t = (cos - cos outer) / (cos inner - cos outer) clamped to [0, 1].
// The film sees the full cone, the falloff ring and the dark outside.
TEST(PunctualLights, SpotLightIsAPointLightInsideItsConeAndDarkOutside) {
    scene::Scene s = litPlane();
    const glm::dvec3 position(0.1, 1.2, -0.1), axis = glm::normalize(glm::dvec3(0.2, -1.0, 0.1)),
                                               intensity(3, 3, 3);
    const double inner = 0.35, outer = 0.6;
    s.spotLights.push_back(
        {glm::vec3(position), glm::vec3(axis), glm::vec3(intensity), float(inner), float(outer)});
    const double cosInner = std::cos(inner), cosOuter = std::cos(outer);
    expectMatches(s, [&](glm::dvec3 x) {
        const glm::dvec3 toLight = position - x;
        const double d2 = glm::dot(toLight, toLight), d = std::sqrt(d2);
        const double t =
            std::clamp((glm::dot(-toLight / d, axis) - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
        return ALBEDO / PI * intensity * (toLight.y / d) / d2 * t * t;
    });
}

}  // namespace
