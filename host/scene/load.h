// Scene loading: picks the importer from the file extension.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "scene/scene.h"

namespace vkpath::scene {

struct LoadOptions {
    std::string cameraName;  // glTF: choose this camera instead of the first
    // Called with the file's geometry as the loaded scene will hold it
    // (instances flattened), counted before any mesh is built; it throws
    // InputError to refuse a scene too large for the machine
    // (app::admitScene). Unset: every scene is admitted.
    std::function<void(const std::string& file, const GeometryCounts& counts)> admit;
};

// .gltf / .glb (glTF 2.0) or .dae (Scotty3D COLLADA). Throws InputError with
// one line naming the file and the problem on any bad input. Warnings (what
// was approximated, what was dropped) go to stderr, one line per kind.
Scene loadScene(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace vkpath::scene
