#include "scene/gltf_materials.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "input_error.h"

namespace vkpath::scene::gltf {
namespace {

class MaterialConverter {
  public:
    MaterialConverter(const std::string& file, TextureImporter& textures, ImportWarnings& warnings)
        : m_file(file), m_textures(textures), m_warnings(warnings) {}

    // The material mapping table of docs/SCENES.md.
    Material convert(const tinygltf::Material& m, size_t index) {
        Material out;
        out.name = m.name.empty() ? fmt::format("material {}", index) : m.name;
        const std::string& name = out.name;
        const auto& pbr = m.pbrMetallicRoughness;
        if (pbr.baseColorFactor.size() != 4)
            fail("material '{}': baseColorFactor needs 4 numbers", name);
        const glm::vec3 base(factor(pbr.baseColorFactor[0], "baseColorFactor", name),
                             factor(pbr.baseColorFactor[1], "baseColorFactor", name),
                             factor(pbr.baseColorFactor[2], "baseColorFactor", name));
        out.alpha = float(factor(pbr.baseColorFactor[3], "baseColorFactor", name));
        const double metallic = factor(pbr.metallicFactor, "metallicFactor", name);
        const double roughness = factor(pbr.roughnessFactor, "roughnessFactor", name);
        const double transmission =
            factor(extensionNumber(m.extensions, "KHR_materials_transmission", "transmissionFactor",
                                   0.0, name),
                   "transmissionFactor", name);
        const double ior = extensionNumber(m.extensions, "KHR_materials_ior", "ior", 1.5, name);
        if (!std::isfinite(ior) || ior < 1.0)
            fail("material '{}': ior {} is not a finite number >= 1", name, ior);

        out.baseColorTexture = m_textures.reference(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                                    pbr.baseColorTexture.extensions, name, "baseColorTexture");
        out.emissiveTexture = m_textures.reference(m.emissiveTexture.index, m.emissiveTexture.texCoord,
                                                   m.emissiveTexture.extensions, name, "emissiveTexture");
        if (pbr.metallicRoughnessTexture.index >= 0)
            m_warnings.addCounted("metallicRoughnessTexture is ignored until vkpath has microfacet materials; the "
                                  "factors are used",
                                  "material", name);
        out.normalTexture = m_textures.reference(m.normalTexture.index, m.normalTexture.texCoord,
                                                 m.normalTexture.extensions, name, "normalTexture");
        if (!std::isfinite(m.normalTexture.scale))
            fail("material '{}': normalTexture.scale is not a finite number", name);
        out.normalScale = float(m.normalTexture.scale);
        // The tangent frame follows the texture coordinates themselves (glTF
        // 2.0, 3.7.2.1), not KHR_texture_transform's: a turned or unevenly
        // scaled normal map tilts its normals the wrong way.
        const TextureRef& normal = out.normalTexture;
        if (normal.present() && (normal.rotation != 0.0f || normal.scale.x != normal.scale.y))
            m_warnings.addCounted("normal maps turned or unevenly scaled by KHR_texture_transform are approximated: "
                                  "the tangent frame does not follow the transform",
                                  "material", name);
        if (m.occlusionTexture.index >= 0)
            m_warnings.addCounted("occlusionTexture is not applied: a path tracer computes occlusion itself",
                                  "material", name);
        if (usesExtensionTexture(m))
            m_warnings.addCounted("textures of material extensions are ignored; their factors are used",
                                  "material", name);
        readAlphaMode(m, out);
        if (metallic > 0.0 && metallic < 1.0)
            m_warnings.addCounted(
                "partly metallic materials are approximated: metallicFactor >= 0.5 as metal, below "
                "as "
                "non-metal",
                "material", name);

        constexpr double SMOOTH =
            0.01;  // roughness at or below which a surface counts as perfectly smooth
        if (metallic >= 0.5) {
            out.reflectance = base;
            out.kind = roughness <= 0.5 ? MaterialKind::Mirror : MaterialKind::Diffuse;
            if (roughness > SMOOTH)
                m_warnings.addCounted(
                    "rough metals are approximated: roughnessFactor <= 0.5 as a mirror, above as "
                    "diffuse",
                    "material", name);
        } else if (transmission >= 0.5) {
            out.kind = MaterialKind::Dielectric;
            out.reflectance = glm::vec3(1.0f);  // glTF's dielectric specular is untinted
            out.transmittance = base;  // KHR_materials_transmission: base colour tints what passes
            out.ior = float(ior);
            if (roughness > SMOOTH)
                m_warnings.addCounted("rough transmission is approximated as smooth glass",
                                      "material", name);
        } else {
            out.kind = MaterialKind::Diffuse;
            out.reflectance = base;
            if (roughness < 0.5 && transmission == 0.0)
                m_warnings.addCounted(
                    "glossy non-metals (roughnessFactor < 0.5) are approximated as Lambertian: the "
                    "specular layer is dropped",
                    "material", name);
        }
        if (transmission > 0.0 && transmission < 1.0 && metallic < 0.5)
            m_warnings.addCounted(
                "partial transmission is approximated: transmissionFactor >= 0.5 as glass, below "
                "as "
                "opaque",
                "material", name);

        glm::dvec3 emissive(0.0);
        if (!m.emissiveFactor.empty()) {
            if (m.emissiveFactor.size() != 3)
                fail("material '{}': emissiveFactor needs 3 numbers", name);
            for (int c = 0; c < 3; ++c)
                emissive[c] = factor(m.emissiveFactor[size_t(c)], "emissiveFactor", name);
        }
        const double strength = extensionNumber(m.extensions, "KHR_materials_emissive_strength",
                                                "emissiveStrength", 1.0, name);
        if (!std::isfinite(strength) || strength < 0.0)
            fail("material '{}': emissiveStrength {} is not a finite number >= 0", name, strength);
        out.emission = glm::vec3(emissive * strength);
        return out;
    }

  private:
    // glTF 2.0 section 3.9.4 "Alpha Coverage": alphaMode (default OPAQUE,
    // which ignores alpha) and, for MASK, alphaCutoff (default 0.5, at least 0;
    // above 1 nothing is left).
    void readAlphaMode(const tinygltf::Material& m, Material& out) const {
        if (m.alphaMode == "OPAQUE") {
            out.alphaMode = AlphaMode::Opaque;
        } else if (m.alphaMode == "MASK") {
            out.alphaMode = AlphaMode::Mask;
        } else if (m.alphaMode == "BLEND") {
            out.alphaMode = AlphaMode::Blend;
        } else {
            fail("material '{}': alphaMode '{}' is not OPAQUE, MASK or BLEND", out.name, m.alphaMode);
        }
        if (!std::isfinite(m.alphaCutoff) || m.alphaCutoff < 0.0)
            fail("material '{}': alphaCutoff {} is not a finite number >= 0", out.name, m.alphaCutoff);
        out.alphaCutoff = float(m.alphaCutoff);
    }

    // A factor in [0, 1]: NaN is an error, anything outside is clamped.
    double factor(double value, const char* what, const std::string& material) {
        if (!std::isfinite(value)) fail("material '{}': {} is not a finite number", material, what);
        if (value < 0.0 || value > 1.0) {
            m_warnings.addCounted("material factors outside [0, 1] are clamped", "material",
                                  material);
            value = std::clamp(value, 0.0, 1.0);
        }
        return value;
    }

    // extension.key as a number, `fallback` when the extension or key is absent.
    double extensionNumber(const tinygltf::ExtensionMap& extensions, const char* extension,
                           const char* key, double fallback, const std::string& material) {
        const auto it = extensions.find(extension);
        if (it == extensions.end()) return fallback;
        if (!it->second.IsObject()) fail("material '{}': {} is not an object", material, extension);
        if (!it->second.Has(key)) return fallback;
        const tinygltf::Value& value = it->second.Get(key);
        if (!value.IsNumber())
            fail("material '{}': {}.{} is not a number", material, extension, key);
        return value.GetNumberAsDouble();
    }

    // Whether a material extension (KHR_materials_transmission's
    // transmissionTexture...) names a texture.
    static bool usesExtensionTexture(const tinygltf::Material& m) {
        for (const auto& [name, value] : m.extensions)
            for (const std::string& key : value.Keys())
                if (key.size() >= 7 && key.compare(key.size() - 7, 7, "Texture") == 0) return true;
        return false;
    }

    template <typename... Args>
    [[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) const {
        throw InputError(
            fmt::format("{}: {}", m_file, fmt::format(format, std::forward<Args>(args)...)));
    }

    const std::string& m_file;
    TextureImporter& m_textures;
    ImportWarnings& m_warnings;
};

}  // namespace

Material convertMaterial(const tinygltf::Material& material, size_t index, const std::string& file,
                         TextureImporter& textures, ImportWarnings& warnings) {
    return MaterialConverter(file, textures, warnings).convert(material, index);
}

}  // namespace vkpath::scene::gltf
