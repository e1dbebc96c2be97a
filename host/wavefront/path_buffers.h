// The per-path buffers of the GPU renderer's waves, allocated from the table
// in wave_sizing.h: as many paths as the sizing allows, fewer where the
// device runs out of memory.
#pragma once

#include <cstdint>
#include <map>

#include "vk/buffer.h"
#include "wavefront/render_types.h"
#include "wavefront/wave_sizing.h"

namespace vkpath::vk {
class Context;
}

namespace vkpath::wavefront {

struct PathBuffers {
    uint32_t pathCount = 0;                  // paths in flight (the wave size)
    std::map<uint32_t, vk::Buffer> buffers;  // by binding, the rows in use
    uint64_t bytes = 0;                      // their device memory
};

// Allocates the per-path buffers for up to pathsPerWave's paths. The heap a
// device reports is shared with other programs and its driver, so a wave
// that should fit may not: out of memory, the paths in flight are halved
// (and rounded as pathsPerWave rounds them) until the buffers fit, down to
// one workgroup's worth, with a warning on stderr. The image does not depend
// on the wave size. (lavapipe never runs out here: its device memory is one
// file, grown and mapped on demand, so an address-space limit makes it crash
// later rather than fail an allocation. maxDeviceMemoryBytes bounds a render
// up front instead: `pathStateBudget`.)
PathBuffers allocatePathBuffers(vk::Context& context, const RenderSettings& settings,
                                KernelForm form, uint32_t shadowSamples, PathExtras extras,
                                uint64_t pathStateBudget);

// Adds each per-path binding to `bindings`: its buffer, or `placeholder`
// where the render does not use the row.
void bindPathBuffers(const PathBuffers& paths, const vk::Buffer& placeholder,
                     std::map<uint32_t, const vk::Buffer*>& bindings);

}  // namespace vkpath::wavefront
