#include "bvh/acceleration_structures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <span>
#include <stdexcept>

#include "input_error.h"
#include "vk/check.h"
#include "vk/context.h"

namespace vkpath::bvh {
namespace {

// The extension's commands, which the loader does not export.
struct Commands {
    PFN_vkCreateAccelerationStructureKHR create;
    PFN_vkDestroyAccelerationStructureKHR destroy;
    PFN_vkGetAccelerationStructureBuildSizesKHR buildSizes;
    PFN_vkCmdBuildAccelerationStructuresKHR build;
    PFN_vkGetAccelerationStructureDeviceAddressKHR address;

    explicit Commands(VkDevice device) {
        auto load = [device](const char* name) {
            PFN_vkVoidFunction f = vkGetDeviceProcAddr(device, name);
            if (!f) throw std::runtime_error(fmt::format("{} is not available", name));
            return f;
        };
        create = reinterpret_cast<PFN_vkCreateAccelerationStructureKHR>(
            load("vkCreateAccelerationStructureKHR"));
        destroy = reinterpret_cast<PFN_vkDestroyAccelerationStructureKHR>(
            load("vkDestroyAccelerationStructureKHR"));
        buildSizes = reinterpret_cast<PFN_vkGetAccelerationStructureBuildSizesKHR>(
            load("vkGetAccelerationStructureBuildSizesKHR"));
        build = reinterpret_cast<PFN_vkCmdBuildAccelerationStructuresKHR>(
            load("vkCmdBuildAccelerationStructuresKHR"));
        address = reinterpret_cast<PFN_vkGetAccelerationStructureDeviceAddressKHR>(
            load("vkGetAccelerationStructureDeviceAddressKHR"));
    }
};

// One geometry of a BLAS: triangles (opaque or alpha-tested) or spheres'
// boxes, as a range of the index array (and of the box array).
struct Geometry {
    bool triangles = true;
    bool opaque = true;
    uint32_t firstIndex = 0;
    uint32_t count = 0;
    uint32_t firstBox = 0;  // spheres
};

// What is built on the host before anything on the device: the arrays the
// kernels read and each BLAS's geometries.
struct Layout {
    std::vector<uint32_t> indices;
    std::vector<VkAabbPositionsKHR> boxes;
    std::vector<shared::RayQueryGeometry> table;
    std::vector<std::vector<Geometry>> bottomLevels;  // the scene's triangles, spheres, objects
    // Per TLAS instance: its BLAS, its custom index and its object-to-world rows.
    struct Placement {
        uint32_t bottomLevel;
        uint32_t customIndex;
        VkTransformMatrixKHR transform;
    };
    std::vector<Placement> placements;
};

constexpr VkTransformMatrixKHR IDENTITY = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
// VkAccelerationStructureInstanceKHR::instanceCustomIndex has 24 bits.
constexpr uint32_t MAX_CUSTOM_INDEX = (1u << 24) - 1;

// The triangles of primitives [begin, end), opaque ones then alpha-tested
// ones, as geometries of `level` (an empty one left out).
void addTriangles(const BvhBuild& bvh, uint32_t begin, uint32_t end,
                  const std::vector<bool>& alphaTested, Layout& layout,
                  std::vector<Geometry>& level) {
    for (const bool opaque : {true, false}) {
        Geometry g{
            .triangles = true, .opaque = opaque, .firstIndex = uint32_t(layout.indices.size())};
        for (uint32_t k = begin; k < end; ++k) {
            const shared::BvhPrimitive& p = bvh.primitives[k];
            if (p.kind != VKP_PRIMITIVE_TRIANGLE) continue;
            const bool tested = p.material < alphaTested.size() && alphaTested[p.material];
            if (tested == opaque) continue;
            layout.indices.insert(layout.indices.end(), {3 * k, 3 * k + 1, 3 * k + 2});
            ++g.count;
        }
        if (g.count > 0) level.push_back(g);
    }
}

// The placement of BLAS `level` with `instance` as its hits' Hit::instance:
// its geometries' table entries, from its custom index on.
void place(Layout& layout, uint32_t level, uint32_t instance,
           const VkTransformMatrixKHR& transform) {
    if (layout.bottomLevels[level].empty()) return;
    const uint32_t customIndex = uint32_t(layout.table.size());
    if (customIndex > MAX_CUSTOM_INDEX)
        throw InputError(fmt::format(
            "--traversal rayquery: the scene places more than {} geometries in the device's "
            "acceleration structure (a custom index has 24 bits)",
            MAX_CUSTOM_INDEX));
    for (const Geometry& g : layout.bottomLevels[level])
        layout.table.push_back({g.firstIndex, g.triangles ? 3u : 1u, instance, 0u});
    layout.placements.push_back({level, customIndex, transform});
}

Layout makeLayout(const BvhBuild& bvh, const std::vector<bool>& alphaTested) {
    if (bvh.primitives.size() > 0xffffffffull / 3)
        throw InputError(fmt::format(
            "--traversal rayquery: {} primitives are more than the device's 32-bit vertex "
            "indices reach",
            bvh.primitives.size()));
    Layout layout;
    const uint32_t sceneEnd =
        bvh.objects.empty() ? uint32_t(bvh.primitives.size()) : bvh.objects.front().firstPrimitive;
    layout.bottomLevels.resize(2 + bvh.objects.size());
    addTriangles(bvh, 0, sceneEnd, alphaTested, layout, layout.bottomLevels[0]);
    Geometry spheres{.triangles = false,
                     .opaque = false,
                     .firstIndex = uint32_t(layout.indices.size()),
                     .firstBox = 0};
    for (uint32_t k = 0; k < sceneEnd; ++k) {
        const shared::BvhPrimitive& p = bvh.primitives[k];
        if (p.kind != VKP_PRIMITIVE_SPHERE) continue;
        const float r = p.p1.x;
        // Padded outward, as the BVH's boxes are: a grazing hit the sphere
        // test finds lies inside.
        layout.boxes.push_back({padBelow(p.p0.x - r), padBelow(p.p0.y - r), padBelow(p.p0.z - r),
                                padAbove(p.p0.x + r), padAbove(p.p0.y + r), padAbove(p.p0.z + r)});
        layout.indices.push_back(k);
        ++spheres.count;
    }
    if (spheres.count > 0) layout.bottomLevels[1].push_back(spheres);
    for (size_t o = 0; o < bvh.objects.size(); ++o) {
        const ObjectTree& object = bvh.objects[o];
        addTriangles(bvh, object.firstPrimitive, object.firstPrimitive + object.primitiveCount,
                     alphaTested, layout, layout.bottomLevels[2 + o]);
    }

    place(layout, 0, VKP_NO_INSTANCE, IDENTITY);
    place(layout, 1, VKP_NO_INSTANCE, IDENTITY);
    for (uint32_t k = 0; k < sceneEnd; ++k) {
        const shared::BvhPrimitive& p = bvh.primitives[k];
        if (p.kind != VKP_PRIMITIVE_INSTANCE) continue;
        // The record's object-to-world rows follow its world-to-object rows.
        VkTransformMatrixKHR transform;
        for (uint32_t row = 0; row < 3; ++row)
            std::memcpy(transform.matrix[row], &bvh.traversalNodes[p.id + 3 + row], 16);
        place(layout, 2 + uint32_t(p.p0.x), k, transform);
    }
    return layout;
}

template <typename T>
vk::Buffer inputArray(vk::Context& context, const std::vector<T>& values, const char* name,
                      VkBufferUsageFlags usage) {
    if (values.empty()) return vk::Buffer(context, 16, vk::MemoryKind::DeviceLocal, name, usage);
    return vk::Buffer::fromSpan(context, std::span(values), name, usage);
}

VkDeviceSize alignUp(VkDeviceSize value, VkDeviceSize alignment) {
    return (value + alignment - 1) / alignment * alignment;
}

}  // namespace

AccelerationStructures::AccelerationStructures(vk::Context& context, const BvhBuild& bvh,
                                               const vk::Buffer& primitives,
                                               const std::vector<bool>& alphaTested)
    : m_context(context) {
    if (!context.info().rayQuery)
        throw InputError(
            fmt::format("--traversal rayquery: {} has no ray queries", context.info().name));
    const Commands vkr(context.device());
    m_destroy = vkr.destroy;
    const VkDevice device = context.device();
    constexpr VkBufferUsageFlags INPUT =
        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR;
    constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR;

    const Layout layout = makeLayout(bvh, alphaTested);
    m_indices = inputArray(context, layout.indices, "ray query indices", INPUT);
    m_boxes = inputArray(context, layout.boxes, "ray query sphere boxes", INPUT);
    m_geometries = inputArray(context, layout.table, "ray query geometries", 0);

    VkPhysicalDeviceAccelerationStructurePropertiesKHR properties{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
    VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties2.pNext = &properties;
    vkGetPhysicalDeviceProperties2(context.physicalDevice(), &properties2);
    const VkDeviceSize scratchAlignment =
        std::max<VkDeviceSize>(properties.minAccelerationStructureScratchOffsetAlignment, 16);

    try {
        // ---- the BLASes: geometries, sizes, storage --------------------------------
        const VkDeviceAddress vertices = primitives.deviceAddress();
        const VkDeviceAddress indices = m_indices.deviceAddress();
        const VkDeviceAddress boxes = m_boxes.deviceAddress();
        const uint32_t vertexCount = uint32_t(std::max<size_t>(bvh.primitives.size(), 1) * 3);
        struct Pending {
            std::vector<VkAccelerationStructureGeometryKHR> geometries;
            std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
            VkAccelerationStructureBuildGeometryInfoKHR info;
            VkDeviceSize scratchOffset = 0;
        };
        std::vector<Pending> pending;
        std::vector<uint32_t> built(layout.bottomLevels.size(),
                                    UINT32_MAX);  // level -> m_bottomLevels
        VkDeviceSize scratchBytes = 0;
        auto sizeAndCreate = [&](Pending& p, VkAccelerationStructureTypeKHR type,
                                 Structure& structure, const char* name) {
            p.info = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
            p.info.type = type;
            p.info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
            p.info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
            p.info.geometryCount = uint32_t(p.geometries.size());
            p.info.pGeometries = p.geometries.data();
            std::vector<uint32_t> counts;
            for (const auto& r : p.ranges) counts.push_back(r.primitiveCount);
            VkAccelerationStructureBuildSizesInfoKHR sizes{
                VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
            vkr.buildSizes(device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &p.info,
                           counts.data(), &sizes);
            structure.storage = vk::Buffer(context, sizes.accelerationStructureSize,
                                           vk::MemoryKind::DeviceLocal, name, STORAGE);
            VkAccelerationStructureCreateInfoKHR create{
                VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
            create.buffer = structure.storage.handle();
            create.size = sizes.accelerationStructureSize;
            create.type = type;
            VK_CHECK(vkr.create(device, &create, nullptr, &structure.handle));
            p.info.dstAccelerationStructure = structure.handle;
            p.scratchOffset = scratchBytes;
            scratchBytes = alignUp(scratchBytes + sizes.buildScratchSize, scratchAlignment);
        };
        for (size_t level = 0; level < layout.bottomLevels.size(); ++level) {
            if (layout.bottomLevels[level].empty()) continue;
            Pending& p = pending.emplace_back();
            for (const Geometry& g : layout.bottomLevels[level]) {
                VkAccelerationStructureGeometryKHR geometry{
                    VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
                // Candidates the kernel tests are reported once each.
                geometry.flags = g.opaque ? VK_GEOMETRY_OPAQUE_BIT_KHR
                                          : VK_GEOMETRY_NO_DUPLICATE_ANY_HIT_INVOCATION_BIT_KHR;
                if (g.triangles) {
                    geometry.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
                    auto& t = geometry.geometry.triangles;
                    t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
                    t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
                    t.vertexData.deviceAddress = vertices;
                    t.vertexStride = 16;
                    t.maxVertex = vertexCount - 1;
                    t.indexType = VK_INDEX_TYPE_UINT32;
                    t.indexData.deviceAddress = indices + 4ull * g.firstIndex;
                } else {
                    geometry.geometryType = VK_GEOMETRY_TYPE_AABBS_KHR;
                    auto& a = geometry.geometry.aabbs;
                    a.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_AABBS_DATA_KHR;
                    a.data.deviceAddress = boxes + sizeof(VkAabbPositionsKHR) * g.firstBox;
                    a.stride = sizeof(VkAabbPositionsKHR);
                }
                p.geometries.push_back(geometry);
                p.ranges.push_back({g.count, 0, 0, 0});
            }
            built[level] = uint32_t(m_bottomLevels.size());
            sizeAndCreate(p, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                          m_bottomLevels.emplace_back(), "ray query BLAS");
        }

        // ---- the TLAS ---------------------------------------------------------------
        std::vector<VkAccelerationStructureInstanceKHR> instances;
        for (const Layout::Placement& placement : layout.placements) {
            VkAccelerationStructureDeviceAddressInfoKHR of{
                VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
            of.accelerationStructure = m_bottomLevels[built[placement.bottomLevel]].handle;
            VkAccelerationStructureInstanceKHR instance{};
            instance.transform = placement.transform;
            instance.instanceCustomIndex = placement.customIndex;
            instance.mask = 0xff;
            instance.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
            instance.accelerationStructureReference = vkr.address(device, &of);
            instances.push_back(instance);
        }
        m_instances = inputArray(context, instances, "ray query instances", INPUT);
        Pending top;
        VkAccelerationStructureGeometryKHR geometry{
            VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
        geometry.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
        geometry.geometry.instances.sType =
            VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
        geometry.geometry.instances.data.deviceAddress = m_instances.deviceAddress();
        top.geometries.push_back(geometry);
        top.ranges.push_back({uint32_t(instances.size()), 0, 0, 0});
        sizeAndCreate(top, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, m_topLevel,
                      "ray query TLAS");

        // ---- build: every BLAS at once, then the TLAS -------------------------------
        vk::Buffer scratch(context, scratchBytes + scratchAlignment, vk::MemoryKind::DeviceLocal,
                           "ray query scratch");
        const VkDeviceAddress scratchBase = alignUp(scratch.deviceAddress(), scratchAlignment);
        std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos;
        std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> ranges;
        for (Pending& p : pending) {
            p.info.scratchData.deviceAddress = scratchBase + p.scratchOffset;
            infos.push_back(p.info);
            ranges.push_back(p.ranges.data());
        }
        top.info.scratchData.deviceAddress = scratchBase + top.scratchOffset;
        const VkAccelerationStructureBuildRangeInfoKHR* topRanges = top.ranges.data();
        VkAccelerationStructureDeviceAddressInfoKHR of{
            VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
        of.accelerationStructure = m_topLevel.handle;
        m_topLevelAddress = vkr.address(device, &of);
        context.submit([&](VkCommandBuffer cmd) {
            VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            barrier.srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
            barrier.dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR;
            if (!infos.empty()) {
                vkr.build(cmd, uint32_t(infos.size()), infos.data(), ranges.data());
                vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                                     VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, 0, 1,
                                     &barrier, 0, nullptr, 0, nullptr);
            }
            vkr.build(cmd, 1, &top.info, &topRanges);
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier, 0, nullptr,
                                 0, nullptr);
        });
    } catch (...) {
        destroy();
        throw;
    }
}

AccelerationStructures::~AccelerationStructures() {
    destroy();
}

void AccelerationStructures::destroy() {
    for (Structure& s : m_bottomLevels)
        if (s.handle) m_destroy(m_context.device(), s.handle, nullptr);
    m_bottomLevels.clear();
    if (m_topLevel.handle) m_destroy(m_context.device(), m_topLevel.handle, nullptr);
    m_topLevel.handle = VK_NULL_HANDLE;
}

void AccelerationStructures::setAddresses(shared::BvhAddresses& addresses) const {
    auto split = [](VkDeviceAddress a) { return glm::uvec2(uint32_t(a), uint32_t(a >> 32)); };
    addresses.accelerationStructure = split(m_topLevelAddress);
    addresses.rayQueryGeometries = split(m_geometries.deviceAddress());
    addresses.rayQueryIndices = split(m_indices.deviceAddress());
}

uint64_t AccelerationStructures::bytes() const {
    uint64_t total = m_topLevel.storage.size() + m_indices.size() + m_boxes.size() +
                     m_instances.size() + m_geometries.size();
    for (const Structure& s : m_bottomLevels) total += s.storage.size();
    return total;
}

}  // namespace vkpath::bvh
