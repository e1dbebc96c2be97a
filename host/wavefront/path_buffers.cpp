#include "wavefront/path_buffers.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "vk/check.h"
#include "vk/context.h"
#include "wavefront/wave_sizing.h"

namespace vkpath::wavefront {

PathBuffers allocatePathBuffers(vk::Context& context, const RenderSettings& settings,
                                KernelForm form, uint32_t shadowSamples, PathExtras extras,
                                uint64_t pathStateBudget) {
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    PathBuffers paths;
    uint32_t w = pathsPerWave(settings, form, shadowSamples, extras, context.info(), pixels,
                              pathStateBudget);
    const uint32_t asked = w;
    for (;;) {
        try {
            for (const PathBufferRow& row : pathBufferRows()) {
                const uint64_t bytes = bytesPerPath(row, form, shadowSamples, extras) * w;
                if (bytes == 0) continue;
                paths.buffers.emplace(
                    row.binding, vk::Buffer(context, bytes, vk::MemoryKind::DeviceLocal, row.name));
                paths.bytes += bytes;
            }
            break;
        } catch (const vk::VulkanError& e) {
            if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY &&
                e.result() != VK_ERROR_OUT_OF_HOST_MEMORY)
                throw;
            paths.buffers.clear();
            paths.bytes = 0;
            RenderSettings fewer = settings;
            fewer.maxPathsInFlight = w / 2;
            const uint32_t next = pathsPerWave(fewer, form, shadowSamples, extras, context.info(),
                                               pixels, pathStateBudget);
            if (next < std::min(settings.workgroupSize, asked) || next >= w)
                throw vk::VulkanError(
                    e.result(),
                    fmt::format("out of device memory for the path state of {} paths in "
                                "flight ({} asked): {}",
                                w, asked, e.what()));
            w = next;
        }
    }
    if (w < asked)
        std::fprintf(stderr,
                     "vkpath: warning: out of device memory for %u paths in flight: %u instead\n",
                     asked, w);
    paths.pathCount = w;
    return paths;
}

void bindPathBuffers(const PathBuffers& paths, const vk::Buffer& placeholder,
                     std::map<uint32_t, const vk::Buffer*>& bindings) {
    for (const PathBufferRow& row : pathBufferRows()) {
        const auto it = paths.buffers.find(row.binding);
        bindings[row.binding] = it != paths.buffers.end() ? &it->second : &placeholder;
    }
}

}  // namespace vkpath::wavefront
