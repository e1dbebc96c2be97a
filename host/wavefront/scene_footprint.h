// What a scene will cost in memory, estimated from its geometry's counts
// before any of it is built, so that a scene too large for the machine is
// refused in one line before its memory is spent (the importers count the
// file first: scene::LoadOptions::admit).
//
// The device side follows the tables' layouts (wavefront/gpu_scene.h): per
// primitive a 48-byte BVH primitive and about one 24-byte BVH node (0.99 nodes
// per primitive on a tessellated sphere, 0.97 on normal-maps; at most two),
// per triangle a 16-byte TriangleVertices record where any vertex attribute
// is kept, and a 16-byte texel per vertex for each attribute. The host side
// adds what building them takes, measured as peak resident memory against
// triangles (docs/BENCHMARKS.md, "Scene size": tools/bench/make-scale-scene
// forests of 1 to 16 balls of 99 k triangles).
#pragma once

#include <cstdint>
#include <string>

#include "scene/scene.h"

namespace vkpath::vk {
struct DeviceInfo;
}

namespace vkpath::wavefront {

struct SceneFootprint {
    uint64_t deviceBytes = 0;  // the scene's arrays (the tables the kernels read)
    std::string largestArray;  // the largest of them, named as vk::ArrayExtent names it
    uint64_t largestArrayBytes = 0;
    uint64_t hostBytes = 0;  // peak host memory of loading, building (and uploading)
};

// The estimate for the GPU renderer (cpuReference false: the tables, their
// staging copies and the BVH build) or the CPU reference (the tables and
// its eight-wide tree). rayQuery: the GPU renderer also builds the device's
// acceleration structures (--traversal rayquery), whose size is lavapipe's,
// measured (docs/BENCHMARKS.md, "Ray queries"); other drivers' are smaller.
SceneFootprint estimateFootprint(const scene::GeometryCounts& counts, bool cpuReference,
                                 bool rayQuery = false);

// The host memory a new allocation may take now: /proc/meminfo's
// MemAvailable (physical memory where that is missing), or
// VKPATH_HOST_MEMORY_BYTES where set (a smaller machine, for tests).
uint64_t availableHostMemory();

// Throws InputError, one line naming `file`, when the scene's estimated host
// memory exceeds `available`.
void admitOnHost(const std::string& file, const scene::GeometryCounts& counts,
                 const SceneFootprint& footprint, uint64_t available);

// Throws InputError, one line naming `file`, when the scene's arrays would
// not fit `device`: the largest past what one buffer may hold, or all of them
// past its largest device-local heap.
void admitOnDevice(const std::string& file, const SceneFootprint& footprint,
                   const vk::DeviceInfo& device);

}  // namespace vkpath::wavefront
