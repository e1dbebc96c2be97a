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

std::optional<Traversal> parseTraversal(const std::string& name) {
    if (name == "compute") return Traversal::Compute;
    if (name == "rayquery") return Traversal::RayQuery;
    return std::nullopt;
}

const char* traversalName(Traversal traversal) {
    return traversal == Traversal::RayQuery ? "rayquery" : "compute";
}

std::string tracingKernel(const char* name, Traversal traversal, bool instances) {
    // The device's structures place instances themselves: one variant for both.
    if (traversal == Traversal::RayQuery) return std::string(name) + "_rayquery";
    return instances ? std::string(name) + "_instanced" : std::string(name);
}

shared::BvhAddresses GpuBvh::addresses() const {
    shared::BvhAddresses a{};
    if (byAddress) {
        a.nodes = split(nodes.deviceAddress());
        a.primitives = split(primitives.deviceAddress());
    }
    if (rayQuery) rayQuery->setAddresses(a);
    return a;
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
    // The device's acceleration structures read triangles from it.
    const VkBufferUsageFlags usage =
        context.info().rayQuery
            ? VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR
            : 0;
    if (bvh.primitives.empty()) {
        // A binding (or an address) needs a buffer; the empty tree never reads it.
        const std::vector<shared::BvhPrimitive> placeholder(1, shared::BvhPrimitive{});
        gpu.primitives =
            vk::Buffer::fromSpan(context, std::span(placeholder), "bvh primitives", usage);
    } else {
        gpu.primitives =
            vk::Buffer::fromSpan(context, std::span(bvh.primitives), "bvh primitives", usage);
    }
    // One texel: the bindings are texel buffers (shared/bvh_buffers.h).
    if (byAddress)
        gpu.placeholder = vk::Buffer(context, 16, vk::MemoryKind::DeviceLocal, "bvh placeholder");
    return gpu;
}

void addAccelerationStructures(vk::Context& context, GpuBvh& gpu, const BvhBuild& bvh,
                               const std::vector<bool>& alphaTested) {
    gpu.rayQuery =
        std::make_unique<AccelerationStructures>(context, bvh, gpu.primitives, alphaTested);
}

std::string describeMemory(const BvhBuild& bvh) {
    return fmt::format("BVH: {} nodes ({}) + {} primitives ({}) = {}", bvh.nodes.size(),
                       formatBytes(bvh.traversalNodeBytes()), bvh.primitives.size(),
                       formatBytes(bvh.primitiveBytes()), formatBytes(bvh.bytes()));
}

}  // namespace vkpath::bvh
