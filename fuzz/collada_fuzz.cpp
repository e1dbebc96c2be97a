// libFuzzer harness: the Scotty3D COLLADA importer (pugixml underneath), through
// loadScene as `vkpath render` and `vkpath scene-info` call it. Every input is a
// .dae; a scene it accepts must satisfy the scene model's invariants.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "scene/load.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    vkpath::fuzz::initialize();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = vkpath::fuzz::writeInput("input.dae", data, size);
    vkpath::fuzz::run([&] { vkpath::fuzz::checkScene(vkpath::scene::loadScene(path)); });
    return 0;
}
