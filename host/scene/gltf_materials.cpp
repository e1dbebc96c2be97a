#include "scene/gltf_materials.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

        out.baseColorTexture =
            m_textures.reference(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                 pbr.baseColorTexture.extensions, name, "baseColorTexture");
        out.emissiveTexture =
            m_textures.reference(m.emissiveTexture.index, m.emissiveTexture.texCoord,
                                 m.emissiveTexture.extensions, name, "emissiveTexture");
        out.metallicRoughnessTexture = m_textures.reference(
            pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
            pbr.metallicRoughnessTexture.extensions, name, "metallicRoughnessTexture");
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
            m_warnings.addCounted(
                "normal maps turned or unevenly scaled by KHR_texture_transform are approximated: "
                "the tangent frame does not follow the transform",
                "material", name);
        if (m.occlusionTexture.index >= 0)
            m_warnings.addCounted(
                "occlusionTexture is not applied: a path tracer computes occlusion itself",
                "material", name);
        if (usesUnreadExtensionTexture(m))
            m_warnings.addCounted(
                "the textures of KHR_materials_specular, KHR_materials_transmission and "
                "KHR_materials_volume are ignored; their factors are used",
                "material", name);
        readAlphaMode(m, out);
        // KHR_materials_specular: the dielectric layer's weight and the tint of
        // its Fresnel at normal incidence.
        const double specular = factor(
            extensionNumber(m.extensions, "KHR_materials_specular", "specularFactor", 1.0, name),
            "specularFactor", name);
        const glm::dvec3 specularColor = extensionVector(
            m.extensions, "KHR_materials_specular", "specularColorFactor", glm::dvec3(1.0), name);

        out.roughness = float(roughness);
        out.metallic = float(metallic);
        out.ior = float(ior);
        out.specular = float(specular);
        out.specularColor = glm::vec3(specularColor);
        const bool metalVaries = out.metallicRoughnessTexture.present() && metallic > 0.0;
        readLayers(m, out);
        readDiffuseTransmission(m, out);
        readIridescence(m, out);
        readAnisotropy(m, out);
        const bool layered = out.clearcoat > 0.0f || out.sheenColor != glm::vec3(0.0f) ||
                             out.diffuseTransmission > 0.0f || out.iridescence > 0.0f;
        if (transmission >= 0.5) {
            // KHR_materials_transmission: the base colour tints what passes,
            // the specular reflection is untinted. Smooth without a roughness
            // texture: the exact delta glass.
            const bool smooth = roughness == 0.0 && !out.metallicRoughnessTexture.present() &&
                                out.anisotropy == 0.0f;
            out.kind = smooth ? MaterialKind::Dielectric : MaterialKind::RoughDielectric;
            out.reflectance = glm::vec3(1.0f);
            out.transmittance = base;
            out.attenuation = volumeAttenuation(m, name);
            readVolumeScatter(m, name, out);
            if (metallic > 0.0)
                m_warnings.addCounted(
                    "metallicFactor of transmissive materials is ignored: they are glass",
                    "material", name);
            if (specular != 1.0 || specularColor != glm::dvec3(1.0))
                m_warnings.addCounted("KHR_materials_specular of transmissive materials is ignored",
                                      "material", name);
            if (layered) {
                m_warnings.addCounted(
                    "KHR_materials_clearcoat, KHR_materials_sheen, "
                    "KHR_materials_diffuse_transmission and KHR_materials_iridescence of "
                    "transmissive materials are ignored: vkpath adds them to the "
                    "metallic-roughness material only",
                    "material", name);
                dropLayers(out);
            }
            // Without KHR_materials_volume the surface is a thin wall: light
            // passes unbent and nothing lies inside.
            out.thinWalled = !m.extensions.count("KHR_materials_volume");
            readDispersion(m, out);
        } else {
            // glTF 2.0 Appendix B, specialised where it is exactly a simpler
            // kind: wholly metal is the conductor with Schlick's F0 = base
            // colour; a non-metal without a specular layer (specularFactor 0)
            // is Lambertian; anything else, and anything under a clear coat or
            // a sheen or with diffuse transmission, is the layered material.
            if (m.extensions.count("KHR_materials_volume_scatter"))
                m_warnings.addCounted(
                    "KHR_materials_volume_scatter without transmission is ignored (vkpath's "
                    "diffuse transmission is thin-walled: no volume behind it)",
                    "material", name);
            out.reflectance = base;
            if (layered)
                out.kind = MaterialKind::MetallicRoughness;
            else if (metallic == 1.0 && !metalVaries)
                out.kind = MaterialKind::Conductor;
            else if (metallic == 0.0 && specular == 0.0)
                out.kind = MaterialKind::Diffuse;
            else
                out.kind = MaterialKind::MetallicRoughness;
        }
        if (transmission > 0.0 && transmission < 1.0)
            m_warnings.addCounted(
                "partial transmission is approximated: transmissionFactor >= 0.5 as glass, below "
                "as opaque",
                "material", name);
        // A texture that no longer changes anything is not uploaded.
        if (out.kind == MaterialKind::Diffuse || out.kind == MaterialKind::Dielectric) {
            out.metallicRoughnessTexture = TextureRef{};
            out.anisotropy = 0.0f;
            out.anisotropyTexture = TextureRef{};
        }

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
            fail("material '{}': alphaMode '{}' is not OPAQUE, MASK or BLEND", out.name,
                 m.alphaMode);
        }
        if (!std::isfinite(m.alphaCutoff) || m.alphaCutoff < 0.0)
            fail("material '{}': alphaCutoff {} is not a finite number >= 0", out.name,
                 m.alphaCutoff);
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

    // extension.key, or null when the extension or key is absent.
    const tinygltf::Value* extensionValue(const tinygltf::ExtensionMap& extensions,
                                          const char* extension, const char* key,
                                          const std::string& material) {
        const auto it = extensions.find(extension);
        if (it == extensions.end()) return nullptr;
        if (!it->second.IsObject()) fail("material '{}': {} is not an object", material, extension);
        if (!it->second.Has(key)) return nullptr;
        return &it->second.Get(key);
    }

    // extension.key as a number, `fallback` when the extension or key is absent.
    double extensionNumber(const tinygltf::ExtensionMap& extensions, const char* extension,
                           const char* key, double fallback, const std::string& material) {
        const tinygltf::Value* found = extensionValue(extensions, extension, key, material);
        if (!found) return fallback;
        const tinygltf::Value& value = *found;
        if (!value.IsNumber())
            fail("material '{}': {}.{} is not a number", material, extension, key);
        return value.GetNumberAsDouble();
    }

    // extension.key as three numbers, `fallback` when the extension or key is absent.
    glm::dvec3 extensionVector(const tinygltf::ExtensionMap& extensions, const char* extension,
                               const char* key, glm::dvec3 fallback, const std::string& material) {
        const tinygltf::Value* found = extensionValue(extensions, extension, key, material);
        if (!found) return fallback;
        const tinygltf::Value& value = *found;
        if (!value.IsArray() || value.ArrayLen() != 3)
            fail("material '{}': {}.{} is not 3 numbers", material, extension, key);
        glm::dvec3 v;
        for (int c = 0; c < 3; ++c) {
            const tinygltf::Value& number = value.Get(c);
            if (!number.IsNumber() || !std::isfinite(number.GetNumberAsDouble()) ||
                number.GetNumberAsDouble() < 0.0)
                fail("material '{}': {}.{} is not 3 finite numbers >= 0", material, extension, key);
            v[c] = number.GetNumberAsDouble();
        }
        return v;
    }

    // KHR_materials_volume's attenuation (Beer-Lambert; absorption, and
    // scattering with KHR_materials_volume_scatter): light that crosses a
    // distance d inside keeps attenuationColor^(d / attenuationDistance), so
    // the coefficient is -ln(attenuationColor) / attenuationDistance per
    // metre (world space, as the extension says). The defaults (distance
    // infinite, colour white) are clear; a colour channel of 0 is taken as
    // 1e-6 (it keeps the coefficient finite: 1e-6 of the light after one
    // attenuationDistance).
    glm::vec3 volumeAttenuation(const tinygltf::Material& m, const std::string& name) {
        const auto volume = m.extensions.find("KHR_materials_volume");
        if (volume == m.extensions.end()) return glm::vec3(0.0f);
        const double distance =
            extensionNumber(m.extensions, "KHR_materials_volume", "attenuationDistance",
                            std::numeric_limits<double>::infinity(), name);
        if (!(distance > 0.0))
            fail("material '{}': attenuationDistance {} is not > 0", name, distance);
        glm::dvec3 color = extensionVector(m.extensions, "KHR_materials_volume", "attenuationColor",
                                           glm::dvec3(1.0), name);
        if (std::isinf(distance) || color == glm::dvec3(1.0)) return glm::vec3(0.0f);
        glm::vec3 attenuation;
        for (int c = 0; c < 3; ++c) {
            if (color[c] > 1.0) {
                m_warnings.addCounted("material factors outside [0, 1] are clamped", "material",
                                      name);
                color[c] = 1.0;
            }
            attenuation[c] = float(-std::log(std::max(color[c], 1e-6)) / distance);
        }
        return attenuation;
    }

    // KHR_materials_volume_scatter: the share of the inside's attenuation
    // that scatters, and how. The extension gives the multi-scatter albedo
    // rho_ms (multiscatterColor, the colour a thick body of the medium
    // shows); its single-scattering albedo is Kulla and Conty's fit (2017),
    // as the extension states: rho_ss = 1 - (4.09712 + 4.20863 rho_ms -
    // sqrt(9.59217 + 41.6808 rho_ms + 17.7126 rho_ms^2))^2.
    void readVolumeScatter(const tinygltf::Material& m, const std::string& name, Material& out) {
        if (!m.extensions.count("KHR_materials_volume_scatter")) return;
        const char* extension = "KHR_materials_volume_scatter";
        glm::dvec3 color =
            extensionVector(m.extensions, extension, "multiscatterColor", glm::dvec3(0.0), name);
        const double g = extensionNumber(m.extensions, extension, "scatterAnisotropy", 0.0, name);
        if (!(g > -1.0 && g < 1.0))
            fail("material '{}': {}.scatterAnisotropy {} is not in (-1, 1)", name, extension, g);
        for (int c = 0; c < 3; ++c) {
            if (color[c] > 1.0) {
                m_warnings.addCounted("material factors outside [0, 1] are clamped", "material",
                                      name);
                color[c] = 1.0;
            }
            // The fit's ends are 0 and 1 up to its six digits (5.8e-6 at 0): snapped,
            // so that the default colour scatters nothing.
            const double rho = color[c];
            const double root =
                4.09712 + 4.20863 * rho - std::sqrt(9.59217 + 41.6808 * rho + 17.7126 * rho * rho);
            out.scatteringAlbedo[c] = rho == 0.0   ? 0.0f
                                      : rho == 1.0 ? 1.0f
                                                   : float(std::clamp(1.0 - root * root, 0.0, 1.0));
        }
        out.scatterAnisotropy = float(g);
        if (out.attenuation == glm::vec3(0.0f) && out.scatteringAlbedo != glm::vec3(0.0f))
            m_warnings.addCounted(
                "KHR_materials_volume_scatter without KHR_materials_volume's attenuationDistance "
                "scatters nothing (the attenuation is the scattering's and absorption's sum)",
                "material", name);
    }

    // KHR_materials_clearcoat and KHR_materials_sheen: the layers over the
    // metallic-roughness material (shaders/shared/metallic_roughness.h),
    // each factor times its texture's channel. A layer of factor 0 is none,
    // whatever its texture says.
    void readLayers(const tinygltf::Material& m, Material& out) {
        const std::string& name = out.name;
        const char* coat = "KHR_materials_clearcoat";
        out.clearcoat =
            float(factor(extensionNumber(m.extensions, coat, "clearcoatFactor", 0.0, name),
                         "clearcoatFactor", name));
        out.clearcoatRoughness =
            float(factor(extensionNumber(m.extensions, coat, "clearcoatRoughnessFactor", 0.0, name),
                         "clearcoatRoughnessFactor", name));
        if (out.clearcoat > 0.0f) {
            out.clearcoatTexture = extensionTexture(m.extensions, coat, "clearcoatTexture", name);
            out.clearcoatRoughnessTexture =
                extensionTexture(m.extensions, coat, "clearcoatRoughnessTexture", name);
            out.clearcoatNormalTexture =
                extensionTexture(m.extensions, coat, "clearcoatNormalTexture", name);
            if (const tinygltf::Value* info =
                    extensionValue(m.extensions, coat, "clearcoatNormalTexture", name);
                info && info->Has("scale")) {
                const tinygltf::Value& scale = info->Get("scale");
                if (!scale.IsNumber() || !std::isfinite(scale.GetNumberAsDouble()))
                    fail("material '{}': clearcoatNormalTexture.scale is not a finite number",
                         name);
                out.clearcoatNormalScale = float(scale.GetNumberAsDouble());
            }
        }
        const char* sheen = "KHR_materials_sheen";
        const glm::dvec3 color =
            extensionVector(m.extensions, sheen, "sheenColorFactor", glm::dvec3(0.0), name);
        for (int c = 0; c < 3; ++c)
            out.sheenColor[c] = float(factor(color[c], "sheenColorFactor", name));
        out.sheenRoughness =
            float(factor(extensionNumber(m.extensions, sheen, "sheenRoughnessFactor", 0.0, name),
                         "sheenRoughnessFactor", name));
        if (out.sheenColor != glm::vec3(0.0f)) {
            out.sheenColorTexture =
                extensionTexture(m.extensions, sheen, "sheenColorTexture", name);
            out.sheenRoughnessTexture =
                extensionTexture(m.extensions, sheen, "sheenRoughnessTexture", name);
        }
    }

    // KHR_materials_diffuse_transmission: the share of the diffuse lobe that
    // passes to the back and its colour, each times its texture. A thin wall
    // in vkpath: with KHR_materials_volume the light would enter a volume
    // (warned).
    void readDiffuseTransmission(const tinygltf::Material& m, Material& out) {
        const std::string& name = out.name;
        const char* extension = "KHR_materials_diffuse_transmission";
        out.diffuseTransmission = float(
            factor(extensionNumber(m.extensions, extension, "diffuseTransmissionFactor", 0.0, name),
                   "diffuseTransmissionFactor", name));
        const glm::dvec3 color = extensionVector(
            m.extensions, extension, "diffuseTransmissionColorFactor", glm::dvec3(1.0), name);
        for (int c = 0; c < 3; ++c)
            out.diffuseTransmissionColor[c] =
                float(factor(color[c], "diffuseTransmissionColorFactor", name));
        if (out.diffuseTransmission == 0.0f) return;
        out.diffuseTransmissionTexture =
            extensionTexture(m.extensions, extension, "diffuseTransmissionTexture", name);
        out.diffuseTransmissionColorTexture =
            extensionTexture(m.extensions, extension, "diffuseTransmissionColorTexture", name);
        if (m.extensions.count("KHR_materials_volume"))
            m_warnings.addCounted(
                "KHR_materials_volume of diffuse-transmitting materials is ignored: vkpath "
                "passes the light to the back of the same point (thin-walled)",
                "material", name);
    }

    // KHR_materials_iridescence: a thin film of index iridescenceIor (> 0)
    // and thickness in [minimum, maximum] nm (each >= 0), its weight and
    // thickness each times its texture.
    void readIridescence(const tinygltf::Material& m, Material& out) {
        const std::string& name = out.name;
        const char* extension = "KHR_materials_iridescence";
        out.iridescence =
            float(factor(extensionNumber(m.extensions, extension, "iridescenceFactor", 0.0, name),
                         "iridescenceFactor", name));
        if (out.iridescence == 0.0f) return;
        const double ior = extensionNumber(m.extensions, extension, "iridescenceIor", 1.3, name);
        if (!std::isfinite(ior) || ior <= 0.0)
            fail("material '{}': iridescenceIor {} is not a finite number > 0", name, ior);
        out.iridescenceIor = float(ior);
        const auto thickness = [&](const char* key, double fallback) {
            const double t = extensionNumber(m.extensions, extension, key, fallback, name);
            if (!std::isfinite(t) || t < 0.0)
                fail("material '{}': {} {} is not a finite number >= 0", name, key, t);
            return float(t);
        };
        out.iridescenceThicknessMinimum = thickness("iridescenceThicknessMinimum", 100.0);
        out.iridescenceThicknessMaximum = thickness("iridescenceThicknessMaximum", 400.0);
        out.iridescenceTexture =
            extensionTexture(m.extensions, extension, "iridescenceTexture", name);
        out.iridescenceThicknessTexture =
            extensionTexture(m.extensions, extension, "iridescenceThicknessTexture", name);
    }

    // KHR_materials_anisotropy: the strength (times the texture's B) and the
    // direction (the texture's RG, else the tangent) turned by the rotation;
    // for the GGX lobes of the metallic-roughness material, the metal
    // (conductor) and rough glass alike.
    void readAnisotropy(const tinygltf::Material& m, Material& out) {
        const std::string& name = out.name;
        const char* extension = "KHR_materials_anisotropy";
        out.anisotropy =
            float(factor(extensionNumber(m.extensions, extension, "anisotropyStrength", 0.0, name),
                         "anisotropyStrength", name));
        const double rotation =
            extensionNumber(m.extensions, extension, "anisotropyRotation", 0.0, name);
        if (!std::isfinite(rotation))
            fail("material '{}': anisotropyRotation is not a finite number", name);
        out.anisotropyRotation = float(rotation);
        if (out.anisotropy == 0.0f) return;
        out.anisotropyTexture =
            extensionTexture(m.extensions, extension, "anisotropyTexture", name);
    }

    // KHR_materials_dispersion: 20 / the Abbe number, >= 0, of a glass with
    // an inside (the extension changes volumetric refraction only: a thin
    // wall, or an opaque material, has none to change).
    void readDispersion(const tinygltf::Material& m, Material& out) {
        const double dispersion =
            extensionNumber(m.extensions, "KHR_materials_dispersion", "dispersion", 0.0, out.name);
        if (!std::isfinite(dispersion) || dispersion < 0.0)
            fail("material '{}': dispersion {} is not a finite number >= 0", out.name, dispersion);
        if (dispersion > 0.0 && out.thinWalled)
            m_warnings.addCounted(
                "KHR_materials_dispersion without KHR_materials_volume is ignored: a thin wall "
                "does not bend the light",
                "material", out.name);
        else
            out.dispersion = float(dispersion);
    }

    static void dropLayers(Material& out) {
        out.iridescence = 0.0f;
        out.iridescenceTexture = out.iridescenceThicknessTexture = TextureRef{};
        out.clearcoat = 0.0f;
        out.sheenColor = glm::vec3(0.0f);
        out.diffuseTransmission = 0.0f;
        out.diffuseTransmissionTexture = out.diffuseTransmissionColorTexture = TextureRef{};
        out.clearcoatTexture = out.clearcoatRoughnessTexture = TextureRef{};
        out.clearcoatNormalTexture = TextureRef{};
        out.sheenColorTexture = out.sheenRoughnessTexture = TextureRef{};
    }

    // extension.key as a textureInfo (index, texCoord, KHR_texture_transform);
    // absent when the extension or key is.
    TextureRef extensionTexture(const tinygltf::ExtensionMap& extensions, const char* extension,
                                const char* key, const std::string& material) {
        const tinygltf::Value* info = extensionValue(extensions, extension, key, material);
        if (!info) return TextureRef{};
        if (!info->IsObject() || !info->Has("index") || !info->Get("index").IsInt())
            fail("material '{}': {}.{} is not a textureInfo with an integer index", material,
                 extension, key);
        const int index = info->Get("index").GetNumberAsInt();
        if (index < 0)
            fail("material '{}': {}.{}.index {} is negative", material, extension, key, index);
        int texCoord = 0;
        if (info->Has("texCoord")) {
            if (!info->Get("texCoord").IsInt())
                fail("material '{}': {}.{}.texCoord is not an integer", material, extension, key);
            texCoord = info->Get("texCoord").GetNumberAsInt();
        }
        tinygltf::ExtensionMap transforms;
        if (info->Has("extensions") && info->Get("extensions").IsObject()) {
            const tinygltf::Value& nested = info->Get("extensions");
            for (const std::string& name : nested.Keys()) transforms[name] = nested.Get(name);
        }
        return m_textures.reference(index, texCoord, transforms, material, key);
    }

    // Whether a material extension whose textures vkpath does not read
    // (KHR_materials_transmission's transmissionTexture...) names a texture.
    static bool usesUnreadExtensionTexture(const tinygltf::Material& m) {
        for (const auto& [name, value] : m.extensions) {
            if (name == "KHR_materials_clearcoat" || name == "KHR_materials_sheen" ||
                name == "KHR_materials_diffuse_transmission" ||
                name == "KHR_materials_iridescence" || name == "KHR_materials_anisotropy")
                continue;
            for (const std::string& key : value.Keys())
                if (key.size() >= 7 && key.compare(key.size() - 7, 7, "Texture") == 0) return true;
        }
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
