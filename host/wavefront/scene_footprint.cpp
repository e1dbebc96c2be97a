#include "wavefront/scene_footprint.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

#include "environment_bytes.h"
#include "format_bytes.h"
#include "input_error.h"
#include "shared/bvh.h"
#include "shared/mesh_attributes.h"
#include "vk/buffer.h"
#include "vk/context.h"

namespace vkpath::wavefront {
namespace {

// Host bytes per primitive beyond the tables, measured (scene_footprint.h):
// the binned builder's references and bins, and the CPU reference's
// eight-wide tree with its primitive copies.
constexpr uint64_t BUILD_BYTES_PER_PRIMITIVE = 48;
constexpr uint64_t WIDE_TREE_BYTES_PER_PRIMITIVE = 170;
// One packed node record holds two children's boxes (shared/bvh.h): 24 bytes
// a node, about one node a primitive.
constexpr uint64_t NODE_BYTES_PER_PRIMITIVE = 24;
constexpr uint64_t ATTRIBUTE_TEXEL_BYTES = 16;  // a vec4 per vertex and attribute
// --traversal rayquery (bvh::AccelerationStructures), per triangle: the index
// array's 12 bytes and lavapipe's structures, 116 bytes in all (115.8 MiB on
// the 1 046 540-triangle bumpy ball; 116.0 and 116.2 on the meshes of
// tests/scene/scene_footprint_test.cpp); per instance a 64-byte TLAS instance
// and its structure's share.
constexpr uint64_t RAY_QUERY_BYTES_PER_TRIANGLE = 116;
constexpr uint64_t RAY_QUERY_BYTES_PER_INSTANCE = 192;

// "12 triangles", "1.6 M triangles and 2 spheres".
std::string geometry(const scene::GeometryCounts& c) {
    auto count = [](uint64_t n, const char* what) {
        if (n < 100'000) return fmt::format("{} {}", n, what);
        return fmt::format("{:.1f} M {}", double(n) / 1e6, what);
    };
    std::string text = count(c.triangles, "triangles");
    if (c.spheres > 0) text += " and " + count(c.spheres, "spheres");
    if (c.instances > 0) text += " placed by " + count(c.instances, "instances");
    return text;
}

}  // namespace

SceneFootprint estimateFootprint(const scene::GeometryCounts& c, bool cpuReference, bool rayQuery) {
    // An instance is a primitive of the scene's tree and a record of
    // VKP_INSTANCE_RECORD_TEXELS texels after the nodes.
    const uint64_t primitives = c.triangles + c.spheres + c.instances;
    const uint64_t attributeVertices = c.normals + c.texcoords + c.colors + c.tangents;
    SceneFootprint f;
    struct Array {
        const char* name;
        uint64_t bytes;
    };
    const Array arrays[] = {
        {"BVH node",
         NODE_BYTES_PER_PRIMITIVE * primitives + 16 * VKP_INSTANCE_RECORD_TEXELS * c.instances},
        {"BVH primitive", sizeof(shared::BvhPrimitive) * primitives},
        {"triangleVertices",
         attributeVertices > 0 ? sizeof(shared::TriangleVertices) * c.triangles : 0},
        {"vertexNormals", ATTRIBUTE_TEXEL_BYTES * c.normals},
        {"vertexTexcoords", ATTRIBUTE_TEXEL_BYTES * c.texcoords},
        {"vertexColors", ATTRIBUTE_TEXEL_BYTES * c.colors},
        {"vertexTangents", ATTRIBUTE_TEXEL_BYTES * c.tangents},
        {"acceleration structure", rayQuery ? RAY_QUERY_BYTES_PER_TRIANGLE * c.triangles +
                                                  RAY_QUERY_BYTES_PER_INSTANCE * c.instances
                                            : 0},
    };
    for (const Array& a : arrays) {
        f.deviceBytes += a.bytes;
        if (a.bytes > f.largestArrayBytes) {
            f.largestArrayBytes = a.bytes;
            f.largestArray = a.name;
        }
    }
    // The loaded scene: positions and indices, the attributes as scene::Mesh
    // keeps them, the spheres.
    const uint64_t sceneBytes =
        12 * c.vertices + 12 * c.triangles + 12 * c.normals + 8 * c.texcoords + 16 * c.colors +
        16 * c.tangents + sizeof(scene::Sphere) * c.spheres + sizeof(scene::Instance) * c.instances;
    f.hostBytes = sceneBytes + BUILD_BYTES_PER_PRIMITIVE * primitives;
    // The GPU renderer holds the tables and, while uploading, their staging
    // copies; the CPU reference reads the tables and its own tree.
    f.hostBytes += cpuReference ? f.deviceBytes + WIDE_TREE_BYTES_PER_PRIMITIVE * primitives
                                : 2 * f.deviceBytes;
    return f;
}

uint64_t availableHostMemory() {
    if (const std::optional<uint64_t> set = environmentBytes("VKPATH_HOST_MEMORY_BYTES"))
        return *set;
    std::ifstream meminfo("/proc/meminfo");
    std::string line;
    while (std::getline(meminfo, line)) {
        std::istringstream in(line);
        std::string key;
        uint64_t kib = 0;
        if (in >> key >> kib && key == "MemAvailable:") return kib * 1024;
    }
    return uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
}

void admitOnHost(const std::string& file, const scene::GeometryCounts& counts,
                 const SceneFootprint& footprint, uint64_t available) {
    if (footprint.hostBytes <= available) return;
    throw InputError(fmt::format(
        "{}: too large for this machine: {} would need about {} of host memory to load and "
        "build ({} on the device), and {} is available",
        file, geometry(counts), formatBytes(footprint.hostBytes),
        formatBytes(footprint.deviceBytes), formatBytes(available)));
}

void admitOnDevice(const std::string& file, const SceneFootprint& footprint,
                   const vk::DeviceInfo& device) {
    const uint64_t oneBuffer = vk::bufferLimits(device).address;
    if (footprint.largestArrayBytes > oneBuffer)
        throw InputError(fmt::format(
            "{}: too large for the device: its {} array would be about {}, more than the {} one "
            "buffer may hold on {} (maxBufferSize, maxMemoryAllocationSize)",
            file, footprint.largestArray, formatBytes(footprint.largestArrayBytes),
            formatBytes(oneBuffer), device.name));
    if (device.deviceLocalMemory > 0 && footprint.deviceBytes > device.deviceLocalMemory)
        throw InputError(fmt::format(
            "{}: too large for the device: its arrays would need about {} of device memory, and "
            "{} has {}",
            file, formatBytes(footprint.deviceBytes), device.name,
            formatBytes(device.deviceLocalMemory)));
}

}  // namespace vkpath::wavefront
