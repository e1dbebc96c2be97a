// glTF materials as the scene model's materials: the mapping table of
// docs/SCENES.md, with each approximation reported once per kind.
#pragma once

#include <cstddef>
#include <string>

#include "scene/gltf_container.h"
#include "scene/gltf_textures.h"
#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene::gltf {

// glTF material `index` of `file`, its textures through `textures`. Throws
// InputError on a value no mapping can take (NaN, an ior below 1, a wrong
// number of factors).
Material convertMaterial(const tinygltf::Material& material, size_t index, const std::string& file,
                         TextureImporter& textures, ImportWarnings& warnings);

}  // namespace vkpath::scene::gltf
