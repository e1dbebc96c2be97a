// glTF textures as the scene model's: each texture a material uses becomes a
// scene::Texture (its image decoded once, with OpenImageIO, its sampler's wrap
// modes and filter), and each use a scene::TextureRef with its texture
// coordinate set and KHR_texture_transform.
#pragma once

#include <map>
#include <string>

#include "scene/gltf_container.h"
#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene::gltf {

class TextureImporter {
  public:
    // Textures and images go into `scene`; `document` must outlive the importer.
    TextureImporter(const Document& document, const std::string& file, Scene& scene,
                    ImportWarnings& warnings);

    // The reference of textureInfo `info` (index, texCoord, extensions) of
    // material `material`, used as `use` ("baseColorTexture"). Absent (with a
    // warning) where the image cannot be decoded or the texture coordinate
    // set is not 0 or 1; InputError where an index is out of range or a
    // transform is malformed.
    TextureRef reference(int index, int texCoord, const tinygltf::ExtensionMap& extensions,
                         const std::string& material, const char* use);

  private:
    // The scene texture of glTF texture `index`, -1 if its image cannot be read.
    int32_t texture(int index, const std::string& material, const char* use);
    // The scene image of glTF image `index`, -1 if it cannot be decoded.
    int32_t image(int index);

    const Document& m_document;
    const std::string& m_file;
    Scene& m_scene;
    ImportWarnings& m_warnings;
    std::map<int, int32_t> m_textures;  // glTF texture -> scene texture (or -1)
    std::map<int, int32_t> m_images;    // glTF image -> scene image (or -1)
};

}  // namespace vkpath::scene::gltf
