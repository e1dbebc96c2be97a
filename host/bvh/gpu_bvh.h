// A BVH in device memory: the node and primitive arrays of a bvh::BvhBuild as
// two device-local buffers, which kernels read through shared/bvh_buffers.h,
// either bound as storage buffers or, for arrays larger than a binding may
// span, by their device addresses.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bvh/acceleration_structures.h"
#include "bvh/bvh.h"
#include "shared/bindings.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace vkpath::vk {
class Context;
}

namespace vkpath::bvh {

// How kernels find a ray's hits: by their own traversal of the tree
// (shaders/shared/bvh_traverse.h) or by the device's acceleration structures
// through ray queries (shaders/shared/bvh_ray_query.h, AccelerationStructures).
enum class Traversal { Compute, RayQuery };

// "compute" or "rayquery" (--traversal); nullopt for any other name.
std::optional<Traversal> parseTraversal(const std::string& name);
const char* traversalName(Traversal traversal);

// The variant of kernel `name`, one that traces rays, for `traversal` and a
// tree with or without instances (cmake/shaders.cmake: `_rayquery`,
// `_instanced`, or the kernel itself).
std::string tracingKernel(const char* name, Traversal traversal, bool instances);

struct GpuBvh {
    vk::Buffer nodes;        // BvhBuild::traversalNodes
    vk::Buffer primitives;   // BvhPrimitive[], leaf order
    bool byAddress = false;  // kernels read both by address (VKP_SPEC_SCENE_BY_ADDRESS)
    vk::Buffer placeholder;  // bound in place of both when byAddress (never read)
    // The device's structures over the same primitives, for kernels that
    // trace by ray queries (addAccelerationStructures); null otherwise.
    std::unique_ptr<AccelerationStructures> rayQuery;

    // What to bind to the kernels' node and primitive bindings.
    const vk::Buffer& nodeBinding() const { return byAddress ? placeholder : nodes; }
    const vk::Buffer& primitiveBinding() const { return byAddress ? placeholder : primitives; }
    // The arrays' device addresses when byAddress, else zeros; and the ray
    // queries' where they are built.
    shared::BvhAddresses addresses() const;
    // Device memory of the two arrays and of the acceleration structures.
    uint64_t bytes() const {
        return nodes.size() + primitives.size() + (rayQuery ? rayQuery->bytes() : 0);
    }
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

// Builds `gpu.rayQuery` for `bvh` (uploaded as `gpu`). `alphaTested`: per
// scene material, whether its triangles are alpha-tested (empty: none is).
// Throws InputError where the device has no ray queries.
void addAccelerationStructures(vk::Context& context, GpuBvh& gpu, const BvhBuild& bvh,
                               const std::vector<bool>& alphaTested);

// One line: node and primitive counts and the memory they take, e.g.
// "BVH: 1234 nodes (38.6 KiB) + 617 primitives (28.9 KiB) = 67.5 KiB".
std::string describeMemory(const BvhBuild& bvh);

}  // namespace vkpath::bvh
