#include "scene/environment.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "input_error.h"

namespace vkpath::scene {
image::Image loadEnvironmentMap(const std::filesystem::path& path, uint64_t maxPixels) {
    const std::string file = path.string();
    // readImage checks the header (OpenEXR attributes, the size) before reading pixels.
    image::Image map = image::readImage(path, maxPixels);

    size_t negative = 0;
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x) {
            glm::vec3& texel = map.at(x, y);
            for (int c = 0; c < 3; ++c) {
                if (!std::isfinite(texel[c]))
                    throw InputError(fmt::format("{}: texel ({}, {}) is not finite ({}, {}, {})",
                                                 file, x, y, texel.x, texel.y, texel.z));
                if (texel[c] < 0.0f) {
                    ++negative;
                    texel[c] = 0.0f;
                }
            }
        }
    if (negative > 0)
        std::fprintf(stderr, "vkpath: warning: %s: %zu negative texel values clamped to 0\n",
                     file.c_str(), negative);
    if (uint64_t(map.width) != 2 * uint64_t(map.height))
        std::fprintf(stderr,
                     "vkpath: warning: %s: %ux%u is not 2:1; the map is stretched over the sphere "
                     "as it is\n",
                     file.c_str(), map.width, map.height);
    return map;
}

}  // namespace vkpath::scene
