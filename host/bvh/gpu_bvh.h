// A BVH in device memory: the node and primitive arrays of a bvh::BvhBuild as
// two storage buffers, bound to a kernel through shared/bvh_buffers.h.
#pragma once

#include <cstdint>
#include <string>

#include "bvh/bvh.h"
#include "vk/buffer.h"

namespace vkpath::vk {
class Context;
}

namespace vkpath::bvh {

struct GpuBvh {
    vk::Buffer nodes;       // BvhNode[], depth-first
    vk::Buffer primitives;  // BvhPrimitive[], leaf order

    uint64_t bytes() const { return nodes.size() + primitives.size(); }
};

// Throws std::length_error, naming the buffer and both sizes, if either array
// is larger than a storage buffer binding may be (`maxStorageBufferRange`:
// 128 MiB on lavapipe, i.e. about 2.8 million primitives). Splitting a large
// scene over several buffers is not implemented.
void checkStorageBufferRange(const BvhBuild& bvh, uint64_t maxStorageBufferRange);

// Uploads both arrays (staging copies) after checkStorageBufferRange against
// the context's device.
GpuBvh uploadBvh(vk::Context& context, const BvhBuild& bvh);

// One line: node and primitive counts and the memory they take, e.g.
// "BVH: 1234 nodes (38.6 KiB) + 617 primitives (28.9 KiB) = 67.5 KiB".
std::string describeMemory(const BvhBuild& bvh);

}  // namespace vkpath::bvh
