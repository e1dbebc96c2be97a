// The kernel harness refuses mistakes that Vulkan would not report clearly.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "shared/bindings.h"
#include "shared/camera.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;

TEST(KernelHarness, ReflectsBindingsAndPushConstants) {
    vk::Kernel generate(test::context(), "generate");
    ASSERT_EQ(generate.reflection().bindings.size(), 2u);
    EXPECT_EQ(generate.reflection().bindings[0].binding, uint32_t(VKP_GENERATE_BINDING_CAMERA));
    EXPECT_EQ(generate.reflection().bindings[1].binding, uint32_t(VKP_GENERATE_BINDING_RAYS));
    EXPECT_EQ(generate.reflection().pushConstantSize, sizeof(shared::GeneratePush));
}

TEST(KernelHarness, RejectsWrongBindingsAndPushSize) {
    vk::Context& context = test::context();
    vk::Kernel generate(context, "generate");
    vk::Buffer a(context, 64), b(context, 64);
    EXPECT_THROW(generate.bind({{VKP_GENERATE_BINDING_CAMERA, &a}}), std::invalid_argument);  // one missing
    EXPECT_THROW(generate.bind({{0, &a}, {1, &b}, {7, &b}}), std::invalid_argument);          // unknown
    EXPECT_THROW(generate.dispatch(1, {{0, &a}, {1, &b}}, uint32_t{0}), std::invalid_argument);  // 4 bytes, not 16
    EXPECT_THROW(vk::Kernel(context, "no_such_kernel"), std::out_of_range);
    EXPECT_THROW(vk::Kernel(context, "generate", {.workgroupSize = 100000}), std::invalid_argument);
}

TEST(KernelHarness, SpecialisedWorkgroupSizesGiveTheSameResult) {
    vk::Context& context = test::context();
    const uint32_t count = 1000;
    shared::Camera camera{};
    camera.forward = {0, 0, -1};
    camera.right = {1, 0, 0};
    camera.up = {0, 1, 0};
    camera.width = 40;
    camera.height = 25;
    vk::Buffer cameraBuffer = vk::Buffer::fromSpan(context, std::span(&camera, 1));
    std::vector<std::vector<shared::Ray>> results;
    for (uint32_t size : {1u, 8u, 64u, 256u}) {
        vk::Buffer rays(context, count * sizeof(shared::Ray));
        vk::Kernel generate(context, "generate", {.workgroupSize = size});
        EXPECT_EQ(generate.workgroupSize(), size);
        const double ms = generate.dispatch(count, {{0, &cameraBuffer}, {1, &rays}},
                                            shared::GeneratePush{0, count, 0, 0});
        EXPECT_GE(ms, 0.0);
        results.push_back(rays.download<shared::Ray>());
    }
    for (size_t r = 1; r < results.size(); ++r)
        for (uint32_t i = 0; i < count; ++i) ASSERT_EQ(results[r][i].direction, results[0][i].direction);
}

TEST(Buffers, UploadDownloadRoundTripAtOffsets) {
    vk::Context& context = test::context();
    std::vector<uint32_t> values(1000);
    for (uint32_t i = 0; i < values.size(); ++i) values[i] = i * 2654435761u;
    vk::Buffer buffer(context, values.size() * 4);
    buffer.clear();
    buffer.upload(std::as_bytes(std::span(values).subspan(100, 50)), 400);
    const auto back = buffer.download<uint32_t>();
    for (uint32_t i = 0; i < values.size(); ++i) ASSERT_EQ(back[i], i >= 100 && i < 150 ? values[i] : 0u) << i;
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
    if (vkCreateBuffer(device, &create, nullptr, &buffer) == VK_SUCCESS) vkDestroyBuffer(device, buffer, nullptr);
}

// The test context turns a validation message into a failure of the running
// test: the guarantee every GPU test relies on.
TEST(Validation, MessageFailsTheRunningTest) {
    vkpath::test::context();
    EXPECT_NONFATAL_FAILURE(createZeroSizeBuffer(), "Vulkan validation");
    EXPECT_GT(vkpath::test::context().validationMessageCount(), 0u);
}

}  // namespace
