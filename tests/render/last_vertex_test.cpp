// The path's last scattering vertex (shared/path_tracer.h lightSamplingAlone):
// on a Lambertian surface whose every emitter is a light, the light samples
// alone estimate what it receives, with weight 1, and no BSDF ray is traced;
// an emitter that is no light (here: a textured one) keeps the BSDF ray, the
// only way to find it. Both estimators are unbiased, so a lamp that is a light
// and the same lamp made a textured emitter (a white 1 x 1 texture: the same
// emission) must light the floor alike, and the first must trace exactly one
// closest-hit ray per path at -m 1 (the camera's). (The test also found that
// the GPU kernels, given no primitive-to-light map when no emitter was a
// light, took the textured lamp for light 0 and weighed its emission by that
// light's density: every emitter now has its entry, gpu_scene.cpp.)
#include <gtest/gtest.h>

#include <cmath>

#include "image/statistics.h"
#include "reference/reference_renderer.h"
#include "scene/scene.h"
#include "support/test_context.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

constexpr double Z_BOUND = 5.0;
constexpr uint32_t SIZE = 32;
constexpr uint32_t SPP = 64;

// A grey floor (albedo 0.5, 4 x 4 m in z = 0, facing +z) under a 1 x 1 m lamp
// of radiance 1 at z = 1 facing down, seen from above and in front of the
// lamp, whose back (which does not emit) the camera sees; a dim point light
// high above, so that light sampling stays on when the lamp is no light.
// `texturedLamp`: the lamp's emission is a white 1 x 1 texture, so it is no
// light.
scene::Scene floorUnderLamp(bool texturedLamp) {
    scene::Scene s;
    scene::Material grey;
    grey.reflectance = glm::vec3(0.5f);
    scene::Material lamp;
    lamp.reflectance = glm::vec3(0.0f);
    lamp.emission = glm::vec3(1.0f);
    if (texturedLamp) {
        s.images.push_back({"white", 1, 1, {glm::u16vec4(65535)}});
        s.textures.push_back({0});
        lamp.emissiveTexture.texture = 0;
    }
    s.materials = {grey, lamp};
    scene::Mesh floor;
    floor.positions = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    floor.material = 0;
    scene::Mesh light;
    light.positions = {{-0.5f, -0.5f, 1},
                       {-0.5f, 0.5f, 1},
                       {0.5f, 0.5f, 1},
                       {0.5f, -0.5f, 1}};  // clockwise from above
    light.texcoords0 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    light.triangles = {{0, 1, 2}, {0, 2, 3}};
    light.material = 1;
    s.meshes = {floor, light};
    s.pointLights.push_back({glm::vec3(0, 0, 3), glm::vec3(0.05f)});
    s.camera.position = {0, -3.5f, 2.5f};
    s.camera.target = {0, 0, 0};
    s.camera.xfovDegrees = 50.0f;
    return s;
}

wavefront::RenderSettings settings(uint32_t maxDepth) {
    wavefront::RenderSettings r;
    r.width = r.height = SIZE;
    r.samplesPerPixel = SPP;
    r.maxDepth = maxDepth;
    return r;
}

// The image's mean over its whole area (floor, the lamp's dark back, nothing else).
image::RegionMean imageMean(const wavefront::RenderResult& r) {
    return image::regionMean(r.image, r.varianceOfMean, [](uint32_t, uint32_t) { return true; });
}

TEST(LastVertex, OnlyTexturedEmittersAreUnsampled) {
    EXPECT_EQ(wavefront::buildSceneTables(floorUnderLamp(false)).info.unsampledEmitters, 0u);
    EXPECT_EQ(wavefront::buildSceneTables(floorUnderLamp(true)).info.unsampledEmitters, 1u);
}

TEST(LastVertex, LightSamplingAloneTracesNoBsdfRayAndLightsAsTheBsdfRayDoes) {
    const uint64_t paths = uint64_t(SIZE) * SIZE * SPP;
    for (bool cpu : {false, true})
        for (wavefront::KernelForm form :
             {wavefront::KernelForm::Megakernel, wavefront::KernelForm::Wavefront}) {
            if (cpu && form == wavefront::KernelForm::Wavefront) continue;
            SCOPED_TRACE(cpu ? "CPU reference" : wavefront::kernelFormName(form));
            auto render = [&](const scene::Scene& s, uint32_t maxDepth) {
                wavefront::RenderSettings r = settings(maxDepth);
                r.kernel = form;
                return cpu ? reference::ReferenceRenderer(s, r).render()
                           : wavefront::GpuRenderer(test::context(), s, r).render();
            };
            const auto sampled = render(floorUnderLamp(false), 1);
            const auto textured = render(floorUnderLamp(true), 1);
            // Every path is the camera's ray and, on the floor, one light sample.
            EXPECT_EQ(sampled.rays.closest, paths);
            EXPECT_GT(sampled.rays.shadow, paths / 2);
            // The textured lamp is found by BSDF rays alone: one more per floor hit.
            EXPECT_GT(textured.rays.closest, paths + paths / 2);
            // One more bounce: the last vertex is the second, the first traces its BSDF ray.
            EXPECT_GT(render(floorUnderLamp(false), 2).rays.closest, paths + paths / 2);

            const auto a = imageMean(sampled), b = imageMean(textured);
            // The floor right under the lamp reflects about 0.5 / pi x 0.7; the image's mean is
            // 0.016.
            EXPECT_GT(a.mean, 0.01);
            const double z = (a.mean - b.mean) / std::sqrt(a.standardError * a.standardError +
                                                           b.standardError * b.standardError);
            EXPECT_LT(std::abs(z), Z_BOUND) << "means " << a.mean << " and " << b.mean;
            RecordProperty(cpu                                         ? "zCpu"
                           : form == wavefront::KernelForm::Megakernel ? "zMegakernel"
                                                                       : "zWavefront",
                           std::to_string(z));
        }
}

}  // namespace
