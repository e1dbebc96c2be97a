// The film stays exact at very high sample counts: the accumulate stage adds
// 2^25 samples of a constant radiance to one pixel (1024 waves of 2^15 paths,
// dispatched through the kernel harness) and the mean is the constant to
// 1e-5 relative. Plain float sums stall once the sum reaches 2^24 times the
// addend and would be off by tens of percent here; the compensated (Kahan)
// sums with `precise` arithmetic keep the error near one float ulp.
#include <gtest/gtest.h>

#include <cmath>

#include "shared/scene_data.h"
#include "shared/wavefront.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

struct Accumulated {
    glm::dvec3 mean;
    uint32_t nonFinite;
};

Accumulated accumulate(const std::vector<glm::vec3>& waveRadiance, uint32_t waves) {
    vk::Context& context = test::context();
    shared::SceneInfo info{};
    info.width = 1;
    info.height = 1;
    const uint32_t count = uint32_t(waveRadiance.size());
    vk::Buffer infoBuffer = vk::Buffer::fromSpan(context, std::span(&info, 1));
    vk::Buffer radiance = vk::Buffer::fromSpan(context, std::span(waveRadiance));
    vk::Buffer counters(context, sizeof(shared::QueueCounters));
    vk::Buffer film(context, sizeof(shared::FilmPixel));
    counters.clear();
    film.clear();
    vk::Kernel kernel(context, "accumulate");
    vk::DescriptorSet set = kernel.bind({{VKP_WF_SCENE_INFO, &infoBuffer}, {VKP_WF_RADIANCE, &radiance},
                                         {VKP_WF_COUNTERS, &counters}, {VKP_WF_FILM, &film}});
    // Every wave in one command buffer, in order, as the renderer records them.
    context.submit([&](VkCommandBuffer cmd) {
        for (uint32_t w = 0; w < waves; ++w) {
            vk::computeBarrier(cmd);
            const shared::WavePush push{w * count, count, 0, 0};
            kernel.record(cmd, set, 1, std::as_bytes(std::span(&push, 1)));
        }
        vk::computeBarrier(cmd);
    });
    const shared::FilmPixel f = film.download<shared::FilmPixel>()[0];
    const double n = double(count) * waves - counters.download<shared::QueueCounters>()[0].nonFinite;
    Accumulated a;
    a.mean = (glm::dvec3(f.sum) - glm::dvec3(f.sumCompensation)) / n;
    a.nonFinite = counters.download<shared::QueueCounters>()[0].nonFinite;
    return a;
}

TEST(FilmAccumulation, TwoToThe25SamplesStayExact) {
    constexpr uint32_t WAVE = 1u << 15, WAVES = 1u << 10;  // 2^25 samples
    // 0.1 is not a float: every addition rounds, which is what drifts.
    const glm::vec3 value(0.1f, 1.0f, 3.7f);
    const auto a = accumulate(std::vector<glm::vec3>(WAVE, value), WAVES);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.mean[c], double(value[c]), 1e-5 * double(value[c])) << c;
    EXPECT_EQ(a.nonFinite, 0u);

    // The bound has power: a plain float sum of the same samples is far off.
    float plain = 0;
    for (uint32_t i = 0; i < WAVE * WAVES; ++i) plain += value.x;
    EXPECT_GT(std::abs(plain / double(WAVE * WAVES) - value.x), 1e-2 * value.x);
}

// NaN and infinite samples are recognised by bit pattern, dropped, counted,
// and never reach the film.
TEST(FilmAccumulation, NonFiniteSamplesAreDroppedAndCounted) {
    std::vector<glm::vec3> samples(1000, glm::vec3(2.0f));
    samples[3].x = std::nanf("");
    samples[10].y = INFINITY;
    samples[500].z = -INFINITY;
    samples[999] = glm::vec3(std::nanf(""));
    const auto a = accumulate(samples, 1);
    EXPECT_EQ(a.nonFinite, 4u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.mean[c], 2.0, 1e-6) << c;
}

// lavapipe ends any shader loop after 65535 iterations (llvmpipe's guard
// against endless loops), and the accumulate stage loops over a pixel's
// samples in a wave, so the renderer caps a wave at 65535 samples per pixel.
// A one-pixel render of 10^5 samples of a constant environment must still
// count every sample.
TEST(FilmAccumulation, RendererKeepsEverySampleOfATinyImage) {
    scene::Scene s;
    s.materials.push_back({});
    s.spheres.push_back({"behind", glm::vec3(0, 0, 10), 1.0f, 0});  // out of view
    s.camera.position = glm::vec3(0);
    s.camera.target = glm::vec3(0, 0, -1);
    scene::Environment env;
    env.color = glm::vec3(0.5f, 0.25f, 2.0f);
    s.environment = env;
    wavefront::RenderSettings settings;
    settings.width = settings.height = 1;
    settings.samplesPerPixel = 100000;
    wavefront::WavefrontRenderer renderer(test::context(), s, settings);
    const auto r = renderer.render();
    EXPECT_GE(r.waves, 2u);
    EXPECT_EQ(r.samplesPerPixel, 100000u);
    EXPECT_NEAR(r.image.pixels[0].x, 0.5f, 1e-6f);
    EXPECT_NEAR(r.image.pixels[0].y, 0.25f, 1e-6f);
    EXPECT_NEAR(r.image.pixels[0].z, 2.0f, 2e-6f);
}

}  // namespace
