// How many paths a wave of the GPU renderer holds, and what they take: the
// table of per-path buffers (PATH_BUFFERS in wave_sizing.cpp: this table
// alone decides their sizes, and path_buffers.h allocates and binds from
// it), the film's windows, and the defaults by device type.
#pragma once

#include <cstdint>
#include <span>

#include "wavefront/render_types.h"

namespace vkpath::vk {
struct DeviceInfo;
}

namespace vkpath::wavefront {

// A per-path buffer of a wave (stages/lib/path_buffers.glsl and queues.glsl
// declare the same).
struct PathBufferRow {
    uint32_t binding;
    const char* name;
    uint64_t bytes;       // per path, or per light sample of a path
    bool perLightSample;  // holds one element per traced light sample
    bool megakernel;      // the megakernel uses it too (else only the wavefront stages)
    bool aovs;            // only renders with the AOVs use it (RenderSettings::surfaceAovs)
    bool wavelengths;     // only kernels with dispersion use it (VKP_FEATURE_DISPERSION)
};

// What a render keeps per path besides every render's state.
struct PathExtras {
    bool aovs = false;         // the AOVs (RenderSettings::surfaceAovs)
    bool wavelengths = false;  // each path's wavelength (kernels with VKP_FEATURE_DISPERSION)
};

// Every per-path buffer, one row each.
std::span<const PathBufferRow> pathBufferRows();

// Bytes per path of `row` in a render of this form that traces `shadowSamples`
// light samples per vertex and keeps `extras`; 0 when the render does not
// use it (a placeholder is bound to it).
uint64_t bytesPerPath(const PathBufferRow& row, KernelForm form, uint32_t shadowSamples,
                      PathExtras extras);

// Device bytes one path in flight takes in the per-path buffers of a kernel
// form whose kernels queue `shadowRaysPerVertex` shadow rays per vertex
// (kernel_features.h) and keeps `extras`.
uint64_t pathStateBytes(KernelForm form, uint32_t shadowRaysPerVertex, PathExtras extras = {});

// The kernel form a device gets without --kernel (measured:
// docs/BENCHMARKS.md, "Kernel forms and specialisation").
KernelForm defaultKernelForm(const vk::DeviceInfo& device);
// The faster traversal on the device (measured: docs/BENCHMARKS.md,
// "Ray queries"); compute where it has no ray queries.
bvh::Traversal defaultTraversal(const vk::DeviceInfo& device);

// The paths one wave may hold unless the settings say: more on a discrete GPU,
// where a wave of 2^20 paths leaves the GPU idle while the host submits the
// next (docs/BENCHMARKS.md, "An NVIDIA H200").
uint32_t defaultPathsInFlight(const vk::DeviceInfo& device);

// The most samples of one pixel (rounds of a pass) a wave may hold: the
// accumulate stage loops over them, and lavapipe cuts every shader loop at
// 65535 iterations.
inline constexpr uint64_t MAX_ROUNDS_PER_WAVE = 65535;

// The device bytes the path state may take: what settings.maxDeviceMemoryBytes
// leaves after the scene and the film (and adaptive sampling's pixel list; no
// limit without it). Throws
// InputError when that leaves room for less than one workgroup's paths.
uint64_t pathStateBudget(const RenderSettings& settings, uint64_t sceneBytes, KernelForm form,
                         uint32_t shadowSamples, PathExtras extras);

// How many paths a wave holds: as many as memory (and `pathStateBudget`
// bytes of path state) allows up to the setting, rounded so that a wave holds
// whole samples of every pixel (or, for images larger than a wave, a whole
// sample is split into equal waves).
uint32_t pathsPerWave(const RenderSettings& settings, KernelForm form, uint32_t shadowSamples,
                      PathExtras extras, const vk::DeviceInfo& device, uint64_t pixels,
                      uint64_t pathStateBudget);

// Pixels per film window: as many as one storage-buffer binding holds
// (maxStorageBufferRange) and one dispatch of accumulate reaches (the
// device's workgroup count), or settings.filmWindowPixels if smaller.
uint32_t filmWindowPixels(const RenderSettings& settings, const vk::DeviceInfo& device);

}  // namespace vkpath::wavefront
