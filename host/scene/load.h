// Scene loading: picks the importer from the file extension.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "scene/scene.h"

namespace vkpath::scene {

// Which meshes that several nodes place are kept once and instanced
// (scene::Instance) rather than copied into world space per node.
enum class Instancing {
    // Those whose copies would add at least INSTANCING_MIN_TRIANGLES
    // triangles. Copies of small meshes trace up to 1.5 times faster (no second tree to
    // enter: docs/BENCHMARKS.md, "Instancing"), and below that many they
    // cost under 100 MiB of device memory and a second or so of BVH build;
    // above it instancing saves both.
    Auto,
    On,   // every mesh placed more than once
    Off,  // none: every placement a world-space copy
};
inline constexpr uint64_t INSTANCING_MIN_TRIANGLES = uint64_t(1) << 20;

struct LoadOptions {
    std::string cameraName;  // glTF: choose this camera instead of the first
    // glTF: render the materials of this KHR_materials_variants variant
    // (scene/gltf_variants.h); empty: the primitives' own
    std::string materialVariant;
    // glTF: meshes placed by several nodes. Emissive meshes are copied
    // whatever this says (their triangles are lights).
    Instancing instancing = Instancing::Auto;
    // Called with the file's geometry as the loaded scene will hold it
    // (an instanced mesh once), counted before any mesh is built; it throws
    // InputError to refuse a scene too large for the machine
    // (app::admitScene). Unset: every scene is admitted.
    std::function<void(const std::string& file, const GeometryCounts& counts)> admit;
};

// .gltf / .glb (glTF 2.0) or .dae (Scotty3D COLLADA). Throws InputError with
// one line naming the file and the problem on any bad input. Warnings (what
// was approximated, what was dropped) go to stderr, one line per kind.
Scene loadScene(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace vkpath::scene
