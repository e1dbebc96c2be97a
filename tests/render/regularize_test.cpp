// Path regularisation (--regularize, shared/bsdf.h regularizedMaterial): it
// widens delta and near-delta lobes only after a path's first non-delta
// scattering, and there it finds light no unregularised path can. Whether the
// GPU forms agree with it on is Scenes/AllScenes.EveryKernelGivesTheSameImage
// (its second settings regularise); its bias against noise is measured by
// `vkpath converge --sweep regularize=...` (docs/TRADEOFFS.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "scene/scene.h"
#include "support/test_context.h"
#include "support/test_scenes.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

wavefront::RenderResult render(const scene::Scene& s, float regularize, uint32_t spp,
                               uint32_t size) {
    wavefront::RenderSettings settings;
    settings.width = size;
    settings.height = size;
    settings.samplesPerPixel = spp;
    settings.maxDepth = 6;
    settings.regularize = regularize;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    return renderer.render();
}

bool sameBits(const image::Image& a, const image::Image& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

// A path that meets only delta lobes is never regularised: a mirror sphere
// and a glass sphere in a constant sky (nothing else to scatter from) render
// the same bits with --regularize 0.3 as without, although the regularising
// kernel holds the conductor and rough-glass code besides.
TEST(Regularize, PathsOfDeltaLobesOnlyAreUntouched) {
    for (const scene::MaterialKind kind :
         {scene::MaterialKind::Mirror, scene::MaterialKind::Dielectric}) {
        SCOPED_TRACE(kind == scene::MaterialKind::Mirror ? "mirror" : "glass");
        scene::Scene s = test::sphereInEnvironment(kind, glm::vec3(0.9f));
        s.environment->color = glm::vec3(0.3f, 0.6f, 1.0f);
        const auto off = render(s, 0.0f, 4, 32);
        const auto on = render(s, 0.3f, 4, 32);
        EXPECT_TRUE(sameBits(off.image, on.image));
    }
}

// A glass sphere on a diffuse floor under a directional light (a delta
// light): the caustic under the sphere is light that goes floor -> glass ->
// light, which no unregularised path finds (a BSDF sample cannot hit a delta
// light and a light sample cannot pass a delta lobe), so without
// regularisation the sphere's shadow is lit by the dim sky alone. Regularised
// (alpha 0.3), the glass seen from the floor is rough, light samples reach the
// sun through it, and the shadow's centre brightens by many standard errors:
// measured at 256 spp 0.054 +- 0.0005 without, 1.12 +- 0.057 with, where 5
// standard errors of the difference are 0.29; at the test's 64 spp the
// margin is still about 3 times the bound.
TEST(Regularize, FindsTheCausticOfADeltaLightThroughGlass) {
    scene::Scene s;
    scene::Material floor;
    floor.kind = scene::MaterialKind::Diffuse;
    floor.reflectance = glm::vec3(0.5f);
    scene::Material glass;
    glass.kind = scene::MaterialKind::Dielectric;
    glass.reflectance = glm::vec3(1.0f);
    glass.ior = 1.5f;
    s.materials = {floor, glass};
    scene::Mesh plane;
    plane.name = "floor";
    const float h = 4.0f;
    plane.positions = {{-h, 0, h}, {h, 0, h}, {h, 0, -h}, {-h, 0, -h}};
    plane.triangles = {{0, 1, 2}, {0, 2, 3}};
    plane.material = 0;
    s.meshes.push_back(plane);
    s.spheres.push_back({"glass", glm::vec3(0.0f, 1.2f, 0.0f), 0.6f, 1});
    s.directionalLights.push_back({glm::vec3(0.0f, -1.0f, 0.0f), glm::vec3(3.0f)});
    scene::Environment sky;
    sky.color = glm::vec3(0.1f);
    s.environment = sky;
    // Straight down onto the floor beside the sphere's axis: the image's
    // centre is the floor under the sphere, seen past its rim.
    s.camera.position = {0.0f, 6.0f, 0.01f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.xfovDegrees = 40.0f;

    auto centre = [](const wavefront::RenderResult& r, double& mean, double& error) {
        // A 4 x 4 block at the middle of the 64 x 64 image: the shadow's centre, seen through the
        // sphere.
        double sum = 0, variance = 0;
        for (uint32_t y = 30; y < 34; ++y)
            for (uint32_t x = 30; x < 34; ++x) {
                const size_t i = size_t(y) * r.image.width + x;
                sum += r.image.pixels[i].y;
                variance += r.varianceOfMean.pixels[i].y;
            }
        mean = sum / 16;
        error = std::sqrt(variance) / 16;
    };
    const auto off = render(s, 0.0f, 64, 64);
    const auto on = render(s, 0.3f, 64, 64);
    EXPECT_EQ(off.nonFiniteSamples + on.nonFiniteSamples, 0u);
    double offMean = 0, offError = 0, onMean = 0, onError = 0;
    centre(off, offMean, offError);
    centre(on, onMean, onError);
    std::printf("  shadow centre: %.4f +- %.4f without, %.4f +- %.4f with --regularize 0.3\n",
                offMean, offError, onMean, onError);
    EXPECT_GT(onMean - offMean, 5.0 * std::sqrt(offError * offError + onError * onError));
}

}  // namespace
