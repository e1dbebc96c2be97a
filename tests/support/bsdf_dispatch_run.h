// Runs tests/kernels/bsdf_dispatch.comp: `count` samples of one material at
// a fixed wo through shared/bsdf.h's dispatch on the GPU, each with the
// dispatch's own evalBsdf and bsdfPdf at the sampled direction.
#pragma once

#include <span>
#include <vector>

#include "kernels/bsdf_dispatch.h"
#include "kernels/microfacet_routines.h"
#include "shared/material.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace vkpath::test {

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
