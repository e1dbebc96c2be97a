// The device's acceleration structures over a BvhBuild (VK_KHR_acceleration_structure),
// for kernels that trace by ray queries (--traversal rayquery; the kernels'
// side is shaders/shared/bvh_ray_query.h):
//
//   - a BLAS over the scene tree's triangles: geometry 0 the opaque ones,
//     geometry 1 those whose material is alpha-tested (non-opaque: the
//     kernel's alpha test decides each candidate);
//   - a BLAS of AABBs over its spheres (the kernel's sphere test finds the hit);
//   - a BLAS per bottom-level tree (BvhBuild::objects), in its own space,
//     with the same two triangle geometries;
//   - a TLAS: the first two at the identity, and one instance per instance
//     primitive, placed by its object-to-world rows (its instance record).
//
// A BLAS or geometry that would be empty is left out. The device reads
// triangles' corners from the primitive array itself (16-byte vertices,
// shaders/shared/bvh.h RayQueryGeometry), through an index array of 12
// bytes per triangle that also leads a hit back to its primitive; spheres'
// boxes are an array of their own.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "bvh/bvh.h"
#include "shared/bvh.h"
#include "vk/buffer.h"

namespace vkpath::vk {
class Context;
}

namespace vkpath::bvh {

class AccelerationStructures {
  public:
    // Builds them on the device from `bvh` and its primitive array uploaded
    // as `primitives` (uploadBvh gives it the build-input usage on devices
    // with ray queries). `alphaTested`: per scene material, whether its
    // triangles are alpha-tested (empty: none is). Needs a context whose
    // device has ray queries (DeviceInfo::rayQuery).
    AccelerationStructures(vk::Context& context, const BvhBuild& bvh, const vk::Buffer& primitives,
                           const std::vector<bool>& alphaTested);
    ~AccelerationStructures();
    AccelerationStructures(const AccelerationStructures&) = delete;
    AccelerationStructures& operator=(const AccelerationStructures&) = delete;

    // Sets the three ray-query fields of `addresses`.
    void setAddresses(shared::BvhAddresses& addresses) const;
    // Device memory: the structures, their instance and box arrays, the
    // index array and the geometry table (not the build's scratch memory).
    uint64_t bytes() const;
    uint32_t bottomLevelCount() const { return uint32_t(m_bottomLevels.size()); }

  private:
    struct Structure {
        vk::Buffer storage;
        VkAccelerationStructureKHR handle = VK_NULL_HANDLE;
    };
    void destroy();

    vk::Context& m_context;
    PFN_vkDestroyAccelerationStructureKHR m_destroy = nullptr;
    std::vector<Structure> m_bottomLevels;
    Structure m_topLevel;
    VkDeviceAddress m_topLevelAddress = 0;
    vk::Buffer m_indices, m_geometries, m_boxes, m_instances;
};

}  // namespace vkpath::bvh
