// The Scotty3D COLLADA importer: COLLADA 1.4 (.dae) as exported from Blender
// with the `CMU462` <extra> profile of CMU 15-462's Scotty3D (analytic
// spheres, mirror / glass / emission materials, area lights). What the
// profile means, and how Scotty3D frames its scenes, is summarised in
// ../shared/scenes/scotty3d/SOURCE.md; the decisions this importer takes
// where Scotty3D is not physical (lamps described twice, point lights without
// falloff, hemisphere "ambient" lights, the camera framing) are documented in
// scotty3d_policy.h, those of reading the file in collada_loader.cpp.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/load.h"
#include "scene/scene.h"

namespace vkpath::scene {

// Loads `path` into world space, +Y up, metres. Throws InputError with one
// line "<file>: <what is wrong>" on bad input. Approximations and dropped
// elements become warnings, one line per kind, printed to stderr as
// "vkpath: warning: <file>: ..." once the whole file has loaded (a file that
// fails prints only its error). When `warnings` is given, the same lines
// (without the "vkpath: warning: " prefix) are appended to it as well.
// options.cameraName picks a camera by node name, camera name or id.
Scene loadCollada(const std::filesystem::path& path, const LoadOptions& options = {},
                  std::vector<std::string>* warnings = nullptr);

}  // namespace vkpath::scene
