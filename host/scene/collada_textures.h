// COLLADA textures as the scene model's: a profile_COMMON
// <texture texture="SAMPLER" texcoord="..."> is resolved through the
// effect's <newparam sid="SAMPLER"><sampler2D> (its <source> surface
// <newparam><surface><init_from>IMAGE</init_from>, or COLLADA 1.5's
// <instance_image>) to <image id="IMAGE"><init_from>FILE</init_from>; an
// exporter that names the image directly in texture="..." is read too.
//
// FILE is held to the glTF importer's rule for external files
// (gltf::uriProblem): a relative path inside the scene's folder, no scheme,
// not absolute, no "..", present, no link out of the folder; anything else
// is an error naming the file, the image and the problem, as for glTF. Only
// images that a material uses are read, each once. An image that cannot be
// decoded is a warning and its texture is left out (texture_images.h).
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "scene/collada_document.h"
#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene::collada {

class TextureImporter {
  public:
    // Images and textures go into `scene`.
    TextureImporter(const Document& document, Scene& scene, ImportWarnings& warnings)
        : m_document(document), m_scene(scene), m_warnings(warnings) {}

    // The reference of `texture` (a <texture> element) in `effect`, used by
    // `what` ("material 'x'"): absent when the image cannot be decoded.
    // The texture reads the primitive's TEXCOORD input that the geometry
    // keeps (Mesh::texcoords0, the lowest set), whatever texcoord="..." binds.
    TextureRef reference(pugi::xml_node texture, pugi::xml_node effect, const std::string& what);

  private:
    int32_t image(pugi::xml_node image, const std::string& what);

    const Document& m_document;
    Scene& m_scene;
    ImportWarnings& m_warnings;
    std::map<std::string, int32_t> m_images;  // image file (canonical) -> scene image (or -1)
};

}  // namespace vkpath::scene::collada
