// libFuzzer harness: environment maps (OpenImageIO's readers underneath). An
// input that starts with the OpenEXR magic is written as input.exr, any other
// as input.hdr (OpenImageIO tries its other readers when the one the extension
// names refuses the file, as it does for `vkpath render -e`). A map it accepts
// must have width x height texels, all finite and non-negative.
//
// The harness caps maps at FUZZ_MAX_PIXELS (2048 x 1024, the bundled sky)
// rather than the default 8192 x 4096 so that a header claiming a large image
// costs a tenth of a second, not seconds: the cap is the same check either way
// (tests/scene/environment_test.cpp covers the default one).
#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fuzz_support.h"
#include "scene/environment.h"

namespace {

constexpr uint64_t FUZZ_MAX_PIXELS = uint64_t(2048) * 1024;
constexpr uint8_t EXR_MAGIC[4] = {0x76, 0x2f, 0x31, 0x01};

void checkMap(const vkpath::image::Image& map) {
    using vkpath::fuzz::finding;
    if (map.width == 0 || map.height == 0 || uint64_t(map.width) * map.height > FUZZ_MAX_PIXELS)
        finding(fmt::format("map of {}x{} texels passed the cap of {}", map.width, map.height,
                            FUZZ_MAX_PIXELS));
    if (map.pixels.size() != size_t(map.width) * map.height)
        finding(
            fmt::format("map of {}x{} has {} texels", map.width, map.height, map.pixels.size()));
    for (const glm::vec3& t : map.pixels)
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(t[c]) || t[c] < 0.0f)
                finding(fmt::format("map texel value {} is not finite and non-negative", t[c]));
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    vkpath::fuzz::initialize();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const bool exr = size >= 4 && std::memcmp(data, EXR_MAGIC, 4) == 0;
    const auto path = vkpath::fuzz::writeInput(exr ? "input.exr" : "input.hdr", data, size);
    vkpath::fuzz::run([&] { checkMap(vkpath::scene::loadEnvironmentMap(path, FUZZ_MAX_PIXELS)); });
    return 0;
}
