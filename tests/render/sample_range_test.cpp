// Sample ranges continue a render: samples [0, 3) then [3, 8), merged by
// their counts, give the image of samples [0, 8) on either renderer, up to
// float rounding; a range starting elsewhere is a different, independent
// image. `vkpath converge` and `vkpath merge` rely on both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "image/metrics.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "support/test_context.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

wavefront::RenderSettings settings() {
    wavefront::RenderSettings s;
    s.width = 24;
    s.height = 18;
    s.samplesPerPixel = 8;
    return s;
}

image::Image merge(const wavefront::RenderResult& a, const wavefront::RenderResult& b) {
    image::Image m(a.image.width, a.image.height);
    for (size_t i = 0; i < m.pixels.size(); ++i)
        m.pixels[i] = (a.image.pixels[i] * float(a.samplesPerPixel) +
                       b.image.pixels[i] * float(b.samplesPerPixel)) /
                      float(a.samplesPerPixel + b.samplesPerPixel);
    return m;
}

template <typename Renderer>
void expectRangesContinueARender(Renderer& renderer) {
    const auto whole = renderer.render();
    const auto first = renderer.render(wavefront::SampleRange{0, 3});
    const auto rest = renderer.render(wavefront::SampleRange{3, 5});
    EXPECT_EQ(first.samplesPerPixel, 3u);
    EXPECT_EQ(rest.samplesPerPixel, 5u);
    // Float rounding of means and sums: a few float ulps (1.2e-7) of each value.
    const image::Image merged = merge(first, rest);
    double worst = 0;
    for (size_t i = 0; i < merged.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            worst =
                std::max(worst, std::abs(double(merged.pixels[i][c]) - whole.image.pixels[i][c]) /
                                    std::max(1.0, std::abs(double(whole.image.pixels[i][c]))));
    EXPECT_LT(worst, 1e-5);
    // Another range is other samples: noise-sized differences, far above rounding.
    const auto later = renderer.render(wavefront::SampleRange{8, 8});
    EXPECT_GT(image::compareImages(later.image, whole.image).overall.rmse, 1e-3);
}

TEST(SampleRange, ContinuesAGpuRender) {
    const scene::Scene scene =
        scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    wavefront::GpuRenderer renderer(test::context(), scene, settings());
    expectRangesContinueARender(renderer);
}

TEST(SampleRange, ContinuesACpuRender) {
    const scene::Scene scene =
        scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    const reference::ReferenceRenderer renderer(scene, settings());
    expectRangesContinueARender(renderer);
}

// Pixel and sample index are separate 32-bit numbers (shared/wavefront.h
// WavePush): the samples just past the old limit of 2^32 paths (sample x
// pixels + pixel), and the last sample indices there are, render on the GPU
// the same samples as on the CPU, within the same-seed bound of
// tests/reference (relMSE 1e-3 on this scene, measured ~1e-14; independent
// renders differ by ~1e-1 at 4 spp). Indices beyond 2^32 - 1 are refused.
TEST(SampleRange, SampleIndicesPastTwoToThe32PathsRenderTheSameSamplesOnGpuAndCpu) {
    const scene::Scene scene =
        scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    wavefront::GpuRenderer gpu(test::context(), scene, settings());
    const reference::ReferenceRenderer cpu(scene, settings());
    const uint32_t pixels = settings().width * settings().height;  // 432
    const uint32_t pastTheOldLimit =
        uint32_t((uint64_t(1) << 32) / pixels);  // its last pixels pass 2^32
    for (const uint32_t first : {pastTheOldLimit - 1, pastTheOldLimit + 1, UINT32_MAX - 3}) {
        SCOPED_TRACE(first);
        const auto g = gpu.render(wavefront::SampleRange{first, 4});
        const auto c = cpu.render(wavefront::SampleRange{first, 4});
        EXPECT_EQ(g.samplesPerPixel, 4u);
        EXPECT_LE(image::compareImages(c.image, g.image).overall.relMse, 1e-3);
        const auto other = cpu.render(wavefront::SampleRange{first - 100, 4});
        EXPECT_GT(image::compareImages(other.image, g.image).overall.relMse, 1e-2)
            << "other samples, other image";
    }
    EXPECT_THROW(gpu.render(wavefront::SampleRange{UINT32_MAX, 2}), std::out_of_range);
}

}  // namespace
