#include "wavefront/wave_sizing.h"

#include <fmt/format.h>

#include <algorithm>

#include "input_error.h"
#include "shared/bvh.h"
#include "shared/path_state.h"
#include "shared/ray.h"
#include "shared/wavefront.h"
#include "vk/context.h"

namespace vkpath::wavefront {
namespace {

constexpr PathBufferRow PATH_BUFFERS[] = {
    {VKP_WF_RAYS, "rays", sizeof(shared::Ray), false, false, false, false},
    {VKP_WF_HITS, "hits", sizeof(shared::Hit), false, false, false, false},
    {VKP_WF_THROUGHPUT, "throughput", sizeof(glm::vec3), false, false, false, false},
    {VKP_WF_RADIANCE, "radiance", sizeof(glm::vec3), false, true, false, false},
    {VKP_WF_VERTEX, "vertices", sizeof(shared::PathVertex), false, false, false, false},
    {VKP_WF_QUEUES, "queues", 3 * sizeof(uint32_t), false, false, false,
     false},  // stages/lib/queues.glsl
    {VKP_WF_SHADOW_RAYS, "shadowRays", sizeof(shared::Ray), true, false, false, false},
    {VKP_WF_SHADOW_RADIANCE, "shadowRadiance", sizeof(glm::vec3), true, false, false, false},
    {VKP_WF_PATH_AOV, "aovs", sizeof(shared::PathAov), false, true, true, false},
    {VKP_WF_PATH_WAVELENGTH, "wavelengths", sizeof(float), false, false, false, true},
};

}  // namespace

std::span<const PathBufferRow> pathBufferRows() {
    return PATH_BUFFERS;
}

uint64_t bytesPerPath(const PathBufferRow& row, KernelForm form, uint32_t shadowSamples,
                      PathExtras extras) {
    if (form == KernelForm::Megakernel && !row.megakernel) return 0;
    if ((row.aovs && !extras.aovs) || (row.wavelengths && !extras.wavelengths)) return 0;
    return row.perLightSample ? row.bytes * shadowSamples : row.bytes;
}

uint64_t pathStateBytes(KernelForm form, uint32_t shadowRaysPerVertex, PathExtras extras) {
    uint64_t total = 0;
    for (const PathBufferRow& row : PATH_BUFFERS)
        total += bytesPerPath(row, form, shadowRaysPerVertex, extras);
    return total;
}

KernelForm defaultKernelForm(const vk::DeviceInfo& device) {
    // Measured faster on each type: docs/BENCHMARKS.md, "Kernel forms and
    // specialisation" and "An NVIDIA H200".
    return device.type == "cpu" ? KernelForm::Megakernel : KernelForm::Wavefront;
}

bvh::Traversal defaultTraversal(const vk::DeviceInfo&) {
    // Measured: lavapipe's ray queries trace 2-4 times slower than the
    // kernels' own traversal (docs/BENCHMARKS.md, "Ray queries"). No device
    // with ray-tracing hardware has been measured, so none defaults to them.
    return bvh::Traversal::Compute;
}

uint32_t defaultPathsInFlight(const vk::DeviceInfo& device) {
    // Measured by wave size: docs/BENCHMARKS.md, "An NVIDIA H200" (a discrete
    // GPU; pathsPerWave still keeps the path state to a quarter of the
    // device's memory). Other types keep 2^20 until measured otherwise.
    return device.type == "discrete" ? 1u << 24 : 1u << 20;
}

uint64_t pathStateBudget(const RenderSettings& s, uint64_t sceneBytes, KernelForm form,
                         uint32_t shadowSamples, PathExtras extras) {
    if (!s.maxDeviceMemoryBytes) return UINT64_MAX;
    const uint64_t pixels = uint64_t(s.width) * s.height;
    const uint64_t taken =
        sceneBytes + pixels * (sizeof(shared::FilmPixel) + (s.adaptive ? sizeof(glm::uvec2) : 0) +
                               (sampleStreams(s) == 2 ? sizeof(shared::FilmStreamPixel) : 0) +
                               (s.surfaceAovs ? sizeof(shared::FilmAovPixel) : 0));
    const uint64_t left = *s.maxDeviceMemoryBytes - std::min(taken, *s.maxDeviceMemoryBytes);
    const uint64_t fewest = std::min<uint64_t>(s.workgroupSize, pixels * s.samplesPerPixel);
    if (left / pathStateBytes(form, shadowSamples, extras) < fewest)
        throw InputError(fmt::format(
            "--max-device-memory {:.3g} MiB: the scene and the film take {:.3g} MiB, leaving room "
            "for "
            "fewer than {} paths in flight",
            *s.maxDeviceMemoryBytes / (1024.0 * 1024.0), taken / (1024.0 * 1024.0), fewest));
    return left;
}

uint32_t pathsPerWave(const RenderSettings& s, KernelForm form, uint32_t shadowSamples,
                      PathExtras extras, const vk::DeviceInfo& device, uint64_t pixels,
                      uint64_t pathStateBudget) {
    const uint64_t total = pathStateBytes(form, shadowSamples, extras);
    uint64_t largest = 1;
    for (const PathBufferRow& row : PATH_BUFFERS)
        largest = std::max(largest, bytesPerPath(row, form, shadowSamples, extras));
    uint64_t limit = s.maxPathsInFlight.value_or(defaultPathsInFlight(device));
    limit = std::min<uint64_t>(limit, device.deviceLocalMemory / 4 / total);
    limit = std::min<uint64_t>(limit, pathStateBudget / total);
    // The largest per-path array must fit one storage-buffer binding.
    limit = std::min<uint64_t>(limit, device.maxStorageBufferRange / largest);
    // One dispatch must reach every path of a wave, and every shadow ray of
    // the shadow stage (lavapipe allows 65535 workgroups).
    limit = std::min<uint64_t>(limit, uint64_t(device.maxWorkgroupCount[0]) * s.workgroupSize /
                                          std::max<uint32_t>(shadowSamples, 1));
    limit = std::max<uint64_t>(limit, 1);
    if (pixels <= limit)
        return uint32_t(
            pixels * std::min<uint64_t>({limit / pixels, s.samplesPerPixel, MAX_ROUNDS_PER_WAVE}));
    const uint64_t wavesPerSample = (pixels + limit - 1) / limit;
    return uint32_t((pixels + wavesPerSample - 1) / wavesPerSample);
}

uint32_t filmWindowPixels(const RenderSettings& s, const vk::DeviceInfo& device) {
    uint64_t limit = device.maxStorageBufferRange / sizeof(shared::FilmPixel);
    limit = std::min<uint64_t>(limit, uint64_t(device.maxWorkgroupCount[0]) * s.workgroupSize);
    if (s.filmWindowPixels) limit = std::min<uint64_t>(limit, s.filmWindowPixels);
    return uint32_t(std::clamp<uint64_t>(limit, 1, UINT32_MAX));
}

}  // namespace vkpath::wavefront
