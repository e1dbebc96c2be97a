// glTF 2.0 import (.gltf with external or embedded buffers, .glb), through
// tinygltf plus vkpath's own checks of everything tinygltf does not check.
// docs/SCENES.md has the material mapping table and the conventions.
#pragma once

#include <filesystem>

#include "scene/load.h"
#include "scene/scene.h"

namespace vkpath::scene {

// Loads the default scene of a glTF file (else its first scene, else every
// root node) into world space:
//   - TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives, indexed
//     (u8/u16/u32) or not; other modes are rejected. Normals go through the
//     inverse transpose, tangents through the transform (w negated under a
//     mirror); a transform with a negative determinant flips the winding so
//     fronts stay counter-clockwise. TEXCOORD_0/1 and COLOR_0 are kept as
//     stored; KHR_mesh_quantization's encodings are read (gltf_meshes.h).
//   - Spheres from vkpath's node extension
//     "VKPATH_sphere": {"radius": r, "material": i}.
//   - Materials mapped to Diffuse / Mirror / Dielectric, emission from
//     emissiveFactor x KHR_materials_emissive_strength;
//     KHR_lights_punctual point, spot and directional lights.
//   - The camera: the first perspective camera in depth-first node order, or
//     the one whose camera or node name is options.cameraName. glTF's yfov is
//     vertical: with an aspectRatio a it becomes xfov = 2 atan(a tan(yfov / 2))
//     and Camera::aspect = a; without one, the camera is taken as square
//     (xfov = yfov, aspect = 1), which keeps yfov vertical on any film at least
//     as wide as it is tall. No camera at all: a default one on the +Z side of
//     the bounding sphere looks at its centre with a 40 degree fov on both axes.
// Throws InputError ("<file>: <problem>") on anything malformed, unsafe (a
// URI that is absolute or leaves the file's folder) or out of range. What is
// approximated or ignored is reported on stderr, one line per kind.
Scene loadGltf(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace vkpath::scene
