#include "bvh/gpu_bvh.h"

#include <fmt/format.h>

#include <span>
#include <vector>

#include "format_bytes.h"
#include "vk/context.h"

namespace vkpath::bvh {

namespace {

glm::uvec2 split(VkDeviceAddress address) {
    return {uint32_t(address), uint32_t(address >> 32)};
}

}  // namespace

shared::BvhAddresses GpuBvh::addresses() const {
    if (!byAddress) return {};
    return {split(nodes.deviceAddress()), split(primitives.deviceAddress())};
}

std::array<vk::ArrayExtent, 2> arrayExtents(const BvhBuild& bvh) {
    return {vk::ArrayExtent{"BVH node", bvh.traversalNodeBytes(), bvh.traversalNodes.size()},
            vk::ArrayExtent{"BVH primitive", bvh.primitiveBytes(), bvh.primitives.size()}};
}

GpuBvh uploadBvh(vk::Context& context, const BvhBuild& bvh) {
    const auto extents = arrayExtents(bvh);
    return uploadBvh(context, bvh,
                     vk::chooseAddressAccess(extents, vk::bufferLimits(context.info())));
}

GpuBvh uploadBvh(vk::Context& context, const BvhBuild& bvh, bool byAddress) {
    GpuBvh gpu;
    gpu.byAddress = byAddress;
    gpu.nodes = vk::Buffer::fromSpan(context, std::span(bvh.traversalNodes), "bvh nodes");
    if (bvh.primitives.empty()) {
        // A binding (or an address) needs a buffer; the empty tree never reads it.
        const std::vector<shared::BvhPrimitive> placeholder(1, shared::BvhPrimitive{});
        gpu.primitives = vk::Buffer::fromSpan(context, std::span(placeholder), "bvh primitives");
    } else {
        gpu.primitives = vk::Buffer::fromSpan(context, std::span(bvh.primitives), "bvh primitives");
    }
    // One texel: the bindings are texel buffers (shared/bvh_buffers.h).
    if (byAddress)
        gpu.placeholder = vk::Buffer(context, 16, vk::MemoryKind::DeviceLocal, "bvh placeholder");
    return gpu;
}

std::string describeMemory(const BvhBuild& bvh) {
    return fmt::format("BVH: {} nodes ({}) + {} primitives ({}) = {}", bvh.nodes.size(),
                       formatBytes(bvh.traversalNodeBytes()), bvh.primitives.size(),
                       formatBytes(bvh.primitiveBytes()), formatBytes(bvh.bytes()));
}

}  // namespace vkpath::bvh
