// Environment maps: equirectangular HDR images of the radiance arriving from
// every direction. The orientation (which texel looks where) is defined once,
// in shaders/shared/environment_map.h, and drawn in docs/SCENES.md.
#pragma once

#include <cstdint>
#include <filesystem>

#include "image/image.h"

namespace vkpath::scene {

// The largest map accepted by default: 8192 x 4096 texels (384 MiB as RGB floats).
inline constexpr uint64_t MAX_ENVIRONMENT_PIXELS = uint64_t(8192) * 4096;

// Reads an equirectangular map (.exr, .hdr, or anything else OpenImageIO
// reads) as linear RGB radiance, W/(m^2 sr). The size is checked from the
// file's header against maxPixels before any pixel memory is allocated.
// Throws InputError ("<file>: <problem>") when the file cannot be read, is
// too large, or holds a NaN or infinite texel. Negative texels (ringing from
// filtered EXRs) are clamped to 0, and a map that is not 2:1 is used
// stretched; each is reported by one warning line on stderr.
image::Image loadEnvironmentMap(const std::filesystem::path& path,
                                uint64_t maxPixels = MAX_ENVIRONMENT_PIXELS);

}  // namespace vkpath::scene
