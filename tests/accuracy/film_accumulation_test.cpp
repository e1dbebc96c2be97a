// The film stays exact at very high sample counts: the accumulate stage adds
// 2^25 samples of a constant radiance to one pixel (1024 waves of 2^15 paths,
// dispatched through the kernel harness) and the mean is the constant to
// 1e-5 relative. Plain float sums stall once the sum reaches 2^24 times the
// addend and would be off by tens of percent here; the compensated (Kahan)
// sums with `precise` arithmetic keep the error near one float ulp. The
// same holds through the whole renderer: 2^25 samples of a constant
// environment in one pixel, over 513 waves.
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
    // A uniform pass of one stream reads no pixel list and no odd film.
    vk::Buffer noPixelList(context, sizeof(glm::uvec2));
    counters.clear();
    film.clear();
    vk::Kernel kernel(context, "accumulate");
    vk::DescriptorSet set = kernel.bind({{VKP_WF_SCENE_INFO, &infoBuffer},
                                         {VKP_WF_RADIANCE, &radiance},
                                         {VKP_WF_COUNTERS, &counters},
                                         {VKP_WF_FILM, &film},
                                         {VKP_WF_PIXEL_LIST, &noPixelList},
                                         {VKP_WF_FILM_ODD, &noPixelList},
                                         {VKP_WF_PATH_AOV, &noPixelList},
                                         {VKP_WF_FILM_AOV, &noPixelList}});
    // Every wave in one command buffer, in order, as the renderer records them.
    context.submit([&](VkCommandBuffer cmd) {
        for (uint32_t w = 0; w < waves; ++w) {
            vk::computeBarrier(cmd);
            const shared::WavePush push{w * count, 0, count, 0, 0};
            kernel.record(cmd, set, 1, std::as_bytes(std::span(&push, 1)));
        }
        vk::computeBarrier(cmd);
    });
    const shared::FilmPixel f = film.download<shared::FilmPixel>()[0];
    const double n =
        double(count) * waves - counters.download<shared::QueueCounters>()[0].nonFinite;
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
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a.mean[c], double(value[c]), 1e-5 * double(value[c])) << c;
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

// The whole renderer at 2^25 samples per pixel of a constant environment
// (0.1, 1, 3.7): one pixel, so 513 waves of at most 65535 samples each
// (lavapipe ends any shader loop after 65535 iterations, and the accumulate
// stage loops over a pixel's samples in a wave). Every sample is counted
// and the mean is the radiance to 1e-5 relative, the criterion; a
// float sum would have stalled at 2^24 samples of 3.7 (an error of ~50%).
TEST(FilmAccumulation, RendererAtTwoToThe25SamplesIsExact) {
    scene::Scene s;
    s.materials.push_back({});
    s.spheres.push_back({"behind", glm::vec3(0, 0, 10), 1.0f, 0});  // out of view
    s.camera.position = glm::vec3(0);
    s.camera.target = glm::vec3(0, 0, -1);
    scene::Environment env;
    const glm::vec3 radiance(0.1f, 1.0f, 3.7f);
    env.color = radiance;
    s.environment = env;
    wavefront::RenderSettings settings;
    settings.width = settings.height = 1;
    settings.samplesPerPixel = 1u << 25;
    settings.maxDepth = 0;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    const auto r = renderer.render();
    EXPECT_EQ(r.waves, 513u);
    EXPECT_EQ(r.samplesPerPixel, 1u << 25);
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r.image.pixels[0][c], radiance[c], 1e-5f * radiance[c]) << c;
}

}  // namespace
