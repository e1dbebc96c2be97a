// A BVH in device memory: the node and primitive arrays of a bvh::BvhBuild as
// two device-local buffers, which kernels read through shared/bvh_buffers.h,
// either bound as storage buffers or, for arrays larger than a binding may
// span, by their device addresses.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "bvh/bvh.h"
#include "shared/bindings.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace vkpath::vk {
class Context;
}

namespace vkpath::bvh {

struct GpuBvh {
    vk::Buffer nodes;        // BvhBuild::traversalNodes
    vk::Buffer primitives;   // BvhPrimitive[], leaf order
    bool byAddress = false;  // kernels read both by address (VKP_SPEC_SCENE_BY_ADDRESS)
    vk::Buffer placeholder;  // bound in place of both when byAddress (never read)

    // What to bind to the kernels' node and primitive bindings.
    const vk::Buffer& nodeBinding() const { return byAddress ? placeholder : nodes; }
    const vk::Buffer& primitiveBinding() const { return byAddress ? placeholder : primitives; }
    // The arrays' device addresses when byAddress, else zeros.
    shared::BvhAddresses addresses() const;
    // Device memory of the two arrays.
    uint64_t bytes() const { return nodes.size() + primitives.size(); }
};

// The specialisation constant that gives a kernel's pipeline the same access path.
inline vk::SpecializationConstant sceneAccessConstant(bool byAddress) {
    return {VKP_SPEC_SCENE_BY_ADDRESS, byAddress ? 1u : 0u};
}

// The node and primitive arrays, for vk::chooseAddressAccess.
std::array<vk::ArrayExtent, 2> arrayExtents(const BvhBuild& bvh);

// Uploads both arrays (staging copies), read by address when either is larger
// than a binding may span (vk::bufferLimits of the context's device). Throws
// InputError when one is larger than even a buffer may be.
GpuBvh uploadBvh(vk::Context& context, const BvhBuild& bvh);
// The same with the access path given (a scene decides for all its arrays at
// once; tests take the address path with small scenes).
GpuBvh uploadBvh(vk::Context& context, const BvhBuild& bvh, bool byAddress);

// One line: node and primitive counts and the memory they take, e.g.
// "BVH: 1234 nodes (38.6 KiB) + 617 primitives (28.9 KiB) = 67.5 KiB".
std::string describeMemory(const BvhBuild& bvh);

}  // namespace vkpath::bvh
