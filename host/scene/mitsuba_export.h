// Writes a loaded scene as a Mitsuba 3 scene (XML + binary PLY meshes), so
// that an independent renderer can render the same scene and `vkpath compare`
// can judge the two images. docs/SCENES.md ("Exporting to Mitsuba 3") has the
// mapping table and what cannot be matched exactly.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace vkpath::scene {

// What the exported integrator, sensor and sampler get: the render settings
// of the vkpath image the Mitsuba one is to be compared with.
struct MitsubaExportSettings {
    uint32_t width = 640;  // film, pixels
    uint32_t height = 480;
    uint32_t samplesPerPixel = 16;
    uint32_t maxDepth = 8;       // vkpath's (pbrt-v4's) bounces: 0 = emitters seen directly only
    uint32_t rouletteDepth = 5;  // vkpath's: Russian roulette from this bounce on
    uint32_t seed = 0;
};

struct MitsubaExportResult {
    std::filesystem::path xml;                 // OUT_DIR/scene.xml
    std::vector<std::filesystem::path> files;  // every file written, scene.xml last
    // One line each for what Mitsuba renders differently (not yet prefixed
    // with "vkpath: warning: ").
    std::vector<std::string> warnings;
};

// Writes OUT_DIR/scene.xml, OUT_DIR/meshes/*.ply and, for an environment
// map, OUT_DIR/envmap.exr (the texels vkpath renders with). Creates OUT_DIR.
// Throws InputError for a degenerate camera or film, std::runtime_error
// naming the file when a file cannot be written.
MitsubaExportResult exportMitsuba(const Scene& scene, const MitsubaExportSettings& settings,
                                  const std::filesystem::path& outDir);

}  // namespace vkpath::scene
