// libFuzzer harness: the glTF 2.0 importer (tinygltf underneath), through
// loadScene. An input that starts with the GLB magic "glTF" is written as
// input.glb, any other as input.gltf, into a folder that also holds a valid
// external buffer (buffer.bin) and links leading out of it (fuzz_support.h):
// a relative URI resolves inside that folder, and opening anything outside it
// is a finding, as is a scene that breaks the scene model's invariants.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fuzz_support.h"
#include "scene/load.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    vkpath::fuzz::initialize();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const auto path = vkpath::fuzz::writeInput(glb ? "input.glb" : "input.gltf", data, size);
    vkpath::fuzz::run([&] { vkpath::fuzz::checkScene(vkpath::scene::loadScene(path)); });
    return 0;
}
