// Runs tests/kernels/bsdf_dispatch.comp: `count` samples of one material at
// a fixed wo through shared/bsdf.h's dispatch on the GPU, each with the
// dispatch's own evalBsdf and bsdfPdf at the sampled direction; and what the
// tests that run it share: their tilted shading normal, directions in a
// frame, the mean weight of a run.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "kernels/bsdf_dispatch.h"
#include "kernels/microfacet_routines.h"
#include "shared/material.h"
#include "shared/sampling.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace vkpath::test {

// A tilted shading normal, so that the dispatch's frame is exercised.
inline const glm::vec3 DISPATCH_NORMAL = glm::normalize(glm::vec3(0.3f, -0.2f, 0.93f));

// The unit direction at cosine cosTheta to frame.n, azimuth phi from frame.s.
inline glm::vec3 directionInFrame(const shared::Frame& frame, double cosTheta, double phi) {
    const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
    return glm::normalize(
        shared::frameToWorld(frame, glm::vec3(float(sinTheta * std::cos(phi)),
                                              float(sinTheta * std::sin(phi)), float(cosTheta))));
}

// The mean weight (red channel) of a run's samples, the invalid ones 0 (so
// the material's albedo at wo), and its standard error.
struct MeanWeight {
    double mean = 0;
    double standardError = 0;
};
inline MeanWeight meanWeight(const std::vector<shared::MicrofacetResult>& results) {
    double sum = 0, sum2 = 0;
    for (const shared::MicrofacetResult& r : results) {
        const double w = (r.flags & 1u) ? double(r.weight.x) : 0.0;
        sum += w;
        sum2 += w * w;
    }
    const double n = double(results.size()), mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

inline std::vector<shared::MicrofacetResult> runBsdfDispatch(const shared::Material& material,
                                                             glm::vec3 wo, glm::vec3 normal,
                                                             uint32_t seed, uint32_t count) {
    vk::Context& context = test::context();
    vk::Buffer results(context, count * sizeof(shared::MicrofacetResult));
    vk::Buffer materials = vk::Buffer::fromSpan(context, std::span(&material, 1), "material");
    vk::Kernel kernel(context, "bsdf_dispatch");
    shared::BsdfDispatchPush push{};
    push.count = count;
    push.seed = seed;
    push.wo = wo;
    push.ng = normal;
    push.ns = normal;
    kernel.dispatch(count, {{0, &results}, {1, &materials}}, push);
    return results.download<shared::MicrofacetResult>();
}

}  // namespace vkpath::test
