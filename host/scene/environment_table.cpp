#include "scene/environment_table.h"

#include <cmath>
#include <numbers>

#include "scene/alias_table.h"

namespace vkpath::scene {

double luminance(const glm::vec3& rgb) { return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z; }

EnvironmentTable buildEnvironmentTable(const image::Image& map) {
    EnvironmentTable table;
    std::vector<double> weights(map.pixels.size());
    for (uint32_t y = 0; y < map.height; ++y) {
        const double sinTheta = std::sin(std::numbers::pi * (y + 0.5) / map.height);
        for (uint32_t x = 0; x < map.width; ++x) {
            const size_t i = size_t(y) * map.width + x;
            weights[i] = std::max(0.0, luminance(map.pixels[i])) * sinTheta;
            table.totalWeight += weights[i];
        }
    }
    table.entries = buildAliasTable(weights);
    return table;
}

}  // namespace vkpath::scene
