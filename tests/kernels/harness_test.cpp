// The kernel harness refuses mistakes that Vulkan would not report clearly.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "kernels/rng_fill.h"
#include "shared/rng.h"
#include "shared/wavefront.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;

TEST(KernelHarness, ReflectsBindingsAndPushConstants) {
    vk::Kernel generate(test::context(), "generate");
    std::vector<uint32_t> bindings;
    for (const auto& b : generate.reflection().bindings) bindings.push_back(b.binding);
    EXPECT_EQ(bindings, (std::vector<uint32_t>{VKP_WF_SCENE_INFO, VKP_WF_CAMERA, VKP_WF_RAYS,
                                               VKP_WF_THROUGHPUT, VKP_WF_RADIANCE, VKP_WF_VERTEX,
                                               VKP_WF_QUEUES, VKP_WF_COUNTERS, VKP_WF_PIXEL_LIST,
                                               VKP_WF_PATH_AOV, VKP_WF_PATH_WAVELENGTH}));
    EXPECT_EQ(generate.reflection().pushConstantSize, sizeof(shared::WavePush));
}

TEST(KernelHarness, RejectsWrongBindingsAndPushSize) {
    vk::Context& context = test::context();
    vk::Kernel fill(context, "rng_fill");
    vk::Buffer a(context, 64), b(context, 64);
    EXPECT_THROW(fill.bind({}), std::invalid_argument);                  // binding 0 missing
    EXPECT_THROW(fill.bind({{0, &a}, {7, &b}}), std::invalid_argument);  // unknown binding
    EXPECT_THROW(fill.bind({{0, &a}, {0, &b}}), std::invalid_argument);  // given twice
    EXPECT_THROW(fill.dispatch(1, {{0, &a}}, uint32_t{0}),
                 std::invalid_argument);  // 4 bytes, not 24
    EXPECT_THROW(vk::Kernel(context, "no_such_kernel"), std::out_of_range);
    EXPECT_THROW(vk::Kernel(context, "generate", {.workgroupSize = 100000}), std::invalid_argument);
}

// Kernels of one name, workgroup size and specialisation share the context's
// pipeline (what a renderer built again for the same scene relies on to skip
// the driver's compiler); any difference gets a pipeline of its own. Each
// kernel keeps its own descriptor sets.
TEST(KernelHarness, SameOptionsShareOnePipeline) {
    vk::Context& context = test::context();
    const vk::Kernel first(context, "rng_fill", {.workgroupSize = 32});
    const vk::Kernel again(context, "rng_fill", {.workgroupSize = 32});
    const vk::Kernel wider(context, "rng_fill", {.workgroupSize = 64});
    const vk::Kernel specialised(context, "rng_fill",
                                 {.workgroupSize = 32, .specialization = {{7, 1}}});
    EXPECT_EQ(&first.reflection(), &again.reflection());
    EXPECT_NE(&first.reflection(), &wider.reflection());
    EXPECT_NE(&first.reflection(), &specialised.reflection());

    vk::Buffer a(context, 64), b(context, 64);
    vk::Kernel fillA(context, "rng_fill"), fillB(context, "rng_fill");
    const vk::DescriptorSet setA = fillA.bind({{0, &a}});
    const vk::DescriptorSet setB = fillB.bind({{0, &b}});
    EXPECT_NE(setA.handle(), setB.handle());
}

TEST(KernelHarness, SpecialisedWorkgroupSizesGiveTheSameResult) {
    vk::Context& context = test::context();
    const uint32_t count = 1000;  // not a multiple of any size below: the bound check matters
    const test::RngFillPush push{count, 10, 10, 3, VKP_SAMPLER_INDEPENDENT, 0};
    std::vector<std::vector<uint32_t>> results;
    for (uint32_t size : {1u, 8u, 64u, 256u}) {
        vk::Buffer bits(context, (count + 256) * sizeof(uint32_t));
        bits.clear();
        vk::Kernel fill(context, "rng_fill", {.workgroupSize = size});
        EXPECT_EQ(fill.workgroupSize(), size);
        EXPECT_GE(fill.dispatch(count, {{0, &bits}}, push), 0.0);
        results.push_back(bits.download<uint32_t>());
    }
    for (size_t r = 1; r < results.size(); ++r) EXPECT_EQ(results[r], results[0]);
    for (uint32_t i = count; i < count + 256; ++i)
        EXPECT_EQ(results[3][i], 0u) << "wrote past count";
}

TEST(Buffers, UploadDownloadRoundTripAtOffsets) {
    vk::Context& context = test::context();
    std::vector<uint32_t> values(1000);
    for (uint32_t i = 0; i < values.size(); ++i) values[i] = i * 2654435761u;
    vk::Buffer buffer(context, values.size() * 4);
    buffer.clear();
    buffer.upload(std::as_bytes(std::span(values).subspan(100, 50)), 400);
    const auto back = buffer.download<uint32_t>();
    for (uint32_t i = 0; i < values.size(); ++i)
        ASSERT_EQ(back[i], i >= 100 && i < 150 ? values[i] : 0u) << i;
    EXPECT_THROW(buffer.upload(std::as_bytes(std::span(values)), 4), std::out_of_range);
}

}  // namespace

namespace {

// An invalid call: a zero-size buffer (VUID-VkBufferCreateInfo-size-00912).
void createZeroSizeBuffer() {
    VkDevice device = vkpath::test::context().device();
    VkBufferCreateInfo create{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    create.size = 0;
    create.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    if (vkCreateBuffer(device, &create, nullptr, &buffer) == VK_SUCCESS)
        vkDestroyBuffer(device, buffer, nullptr);
}

// The test context turns a validation message into a failure of the running
// test: the guarantee every GPU test relies on.
TEST(Validation, MessageFailsTheRunningTest) {
    vkpath::test::context();
    EXPECT_NONFATAL_FAILURE(createZeroSizeBuffer(), "Vulkan validation");
    EXPECT_GT(vkpath::test::context().validationMessageCount(), 0u);
}

}  // namespace
