// Absorption inside glass (KHR_materials_volume, shared/path_tracer.h
// mediumTransmittance): Beer-Lambert along the path inside, checked where it
// is exact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "scene/scene.h"
#include "support/test_context.h"
#include "support/test_scenes.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

wavefront::RenderResult render(const scene::Scene& s, wavefront::KernelForm form) {
    wavefront::RenderSettings settings;
    settings.width = 33;  // odd: the middle pixel looks through the sphere's centre
    settings.height = 33;
    settings.samplesPerPixel = 4;
    settings.maxDepth = 8;
    settings.kernel = form;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    return renderer.render();
}

// A unit sphere of index 1 (no refraction, no reflection: Fresnel is 0) that
// absorbs (0.5, 1, 2) per metre, in a white sky: the middle pixel's ray
// crosses the diameter, so it keeps exp(-2 sigma) of the sky, exactly but for
// the pixel's jitter: a ray at angle theta from the axis passes the centre at
// d = 4 sin theta, its chord is 2 sqrt(1 - d^2), shorter by at most d^2;
// the pixel's half diagonal is theta = atan(sqrt(2) tan(20 deg) / 33), so
// d^2 <= 0.0039, and exp(-2 sigma) <= middle <= exp(-2 sigma + 0.0039 sigma).
// Outside the sphere the sky is 1. The wavefront and the megakernel give the
// same bits.
TEST(Absorption, ChordThroughAnIndexMatchedSphereIsBeerLambert) {
    scene::Scene s =
        test::sphereInEnvironment(scene::MaterialKind::Dielectric, glm::vec3(1.0f), 1.0f);
    s.materials[0].attenuation = {0.5f, 1.0f, 2.0f};
    const auto wavefront = render(s, wavefront::KernelForm::Wavefront);
    const auto megakernel = render(s, wavefront::KernelForm::Megakernel);
    ASSERT_EQ(wavefront.image.pixels.size(), megakernel.image.pixels.size());
    EXPECT_EQ(std::memcmp(wavefront.image.pixels.data(), megakernel.image.pixels.data(),
                          wavefront.image.pixels.size() * sizeof(glm::vec3)),
              0);
    const glm::vec3 middle = wavefront.image.pixels[16 * 33 + 16];
    const glm::vec3 sigma = s.materials[0].attenuation;
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(middle[c], std::exp(-2.0f * sigma[c]) * (1.0f - 1e-6f)) << c;
        EXPECT_LE(middle[c], std::exp((-2.0f + 0.0039f) * sigma[c]) * (1.0f + 1e-6f)) << c;
    }
    const glm::vec3 corner = wavefront.image.pixels[0];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(corner[c], 1.0f, 1e-6f) << c;
}

// Absorption only darkens: the same glass sphere (index 1.5) in the white
// sky, clear and absorbing, with the same seed; the absorbing one is
// nowhere brighter and darker on the whole.
TEST(Absorption, AbsorbingGlassIsNowhereBrighter) {
    scene::Scene clear =
        test::sphereInEnvironment(scene::MaterialKind::Dielectric, glm::vec3(1.0f), 1.5f);
    scene::Scene absorbing = clear;
    absorbing.materials[0].attenuation = glm::vec3(1.0f);
    const auto a = render(clear, wavefront::KernelForm::Megakernel);
    const auto b = render(absorbing, wavefront::KernelForm::Megakernel);
    double sumA = 0, sumB = 0;
    for (size_t i = 0; i < a.image.pixels.size(); ++i) {
        EXPECT_LE(b.image.pixels[i].y, a.image.pixels[i].y + 1e-6f) << i;
        sumA += a.image.pixels[i].y;
        sumB += b.image.pixels[i].y;
    }
    EXPECT_LT(sumB, 0.95 * sumA);
}

}  // namespace
