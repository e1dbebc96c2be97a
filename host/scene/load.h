// Scene loading: picks the importer from the file extension.
#pragma once

#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace vkpath::scene {

struct LoadOptions {
    std::string cameraName;  // glTF: choose this camera instead of the first
};

// .gltf / .glb (glTF 2.0) or .dae (Scotty3D COLLADA). Throws InputError with
// one line naming the file and the problem on any bad input. Warnings (what
// was approximated, what was dropped) go to stderr, one line per kind.
Scene loadScene(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace vkpath::scene
