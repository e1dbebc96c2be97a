#include "bvh/gpu_bvh.h"

#include <fmt/format.h>

#include <span>
#include <stdexcept>
#include <vector>

#include "vk/context.h"

namespace vkpath::bvh {

namespace {

std::string formatBytes(uint64_t bytes) {
    if (bytes < 1024) return fmt::format("{} B", bytes);
    if (bytes < 1024 * 1024) return fmt::format("{:.1f} KiB", bytes / 1024.0);
    return fmt::format("{:.1f} MiB", bytes / (1024.0 * 1024.0));
}

}  // namespace

void checkStorageBufferRange(const BvhBuild& bvh, uint64_t maxStorageBufferRange) {
    auto check = [&](const char* what, uint64_t bytes, size_t count) {
        if (bytes > maxStorageBufferRange)
            throw std::length_error(fmt::format(
                "BVH {} buffer would be {} ({} elements), more than the device's maxStorageBufferRange "
                "of {}; splitting the BVH over several buffers is not implemented",
                what, formatBytes(bytes), count, formatBytes(maxStorageBufferRange)));
    };
    check("node", bvh.nodeBytes(), bvh.nodes.size());
    check("primitive", bvh.primitiveBytes(), bvh.primitives.size());
}

GpuBvh uploadBvh(vk::Context& context, const BvhBuild& bvh) {
    checkStorageBufferRange(bvh, context.info().maxStorageBufferRange);
    GpuBvh gpu;
    gpu.nodes = vk::Buffer::fromSpan(context, std::span(bvh.nodes), "bvh nodes");
    if (bvh.primitives.empty()) {
        // A binding needs a buffer; the empty tree never reads it.
        const std::vector<shared::BvhPrimitive> placeholder(1, shared::BvhPrimitive{});
        gpu.primitives = vk::Buffer::fromSpan(context, std::span(placeholder), "bvh primitives");
    } else {
        gpu.primitives = vk::Buffer::fromSpan(context, std::span(bvh.primitives), "bvh primitives");
    }
    return gpu;
}

std::string describeMemory(const BvhBuild& bvh) {
    return fmt::format("BVH: {} nodes ({}) + {} primitives ({}) = {}", bvh.nodes.size(),
                       formatBytes(bvh.nodeBytes()), bvh.primitives.size(),
                       formatBytes(bvh.primitiveBytes()), formatBytes(bvh.bytes()));
}

}  // namespace vkpath::bvh
