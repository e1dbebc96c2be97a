// COLLADA materials as Scotty3D reads them, bound per instance through
// <bind_material> symbols and read once each:
// - a CMU462 <mirror>, <glass>, <refraction> or <emission> replaces the
//   profile_COMMON material; otherwise the Phong/Lambert <diffuse> colour is
//   a Lambertian albedo (specular ignored), 0.5 grey without one;
// - an <emission>-only material reflects nothing (Scotty3D's EmissionBSDF),
//   so its reflectance is 0;
// - a <diffuse><texture> is the albedo (reflectance 1 times the texture,
//   collada_textures.h); Scotty3D reads no textures.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene/collada_document.h"
#include "scene/collada_textures.h"
#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene::collada {

// <instance_material symbol target> pairs in document order.
using Bindings = std::vector<std::pair<std::string, std::string>>;

class Materials {
  public:
    // Materials are appended to the scene's as first used, with the images
    // and textures they use.
    Materials(const Document& document, ImportWarnings& warnings, Scene& scene)
        : m_document(document),
          m_warnings(warnings),
          m_materials(scene.materials),
          m_textures(document, scene, warnings) {}

    // The scene material that `symbol` is bound to in `bindings`; as in
    // Scotty3D, an unbound or empty symbol takes the instance's first binding,
    // and no binding at all Scotty3D's grey 0.5 default.
    uint32_t forSymbol(const std::string& symbol, const Bindings& bindings,
                       const std::string& nodeName);

  private:
    uint32_t materialIndex(const std::string& targetUrl, const std::string& context);
    Material readMaterial(pugi::xml_node material);
    uint32_t defaultMaterial();

    const Document& m_document;
    ImportWarnings& m_warnings;
    std::vector<Material>& m_materials;
    TextureImporter m_textures;
    std::map<std::string, uint32_t> m_materialsById;
    std::optional<uint32_t> m_defaultMaterial;
};

}  // namespace vkpath::scene::collada
