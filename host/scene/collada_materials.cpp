#include "scene/collada_materials.h"

#include <fmt/format.h>

namespace vkpath::scene::collada {

uint32_t Materials::defaultMaterial() {
    if (!m_defaultMaterial) {
        Material m;
        m.name = "default";
        m.reflectance = glm::vec3(0.5f);  // Scotty3D's DiffuseBSDF for unbound meshes
        m_defaultMaterial = static_cast<uint32_t>(m_materials.size());
        m_materials.push_back(m);
    }
    return *m_defaultMaterial;
}

uint32_t Materials::forSymbol(const std::string& symbol, const Bindings& bindings,
                              const std::string& nodeName) {
    const std::string context = fmt::format("node '{}'", nodeName);
    if (!symbol.empty())
        for (const auto& [s, target] : bindings)
            if (s == symbol) return materialIndex(target, context);
    if (!symbol.empty())
        m_warnings.addExample(
            "unbound-symbol",
            fmt::format("{}: material symbol '{}' is not bound; using {} (as Scotty3D)", context,
                        symbol, bindings.empty() ? "grey 0.5" : "the instance's first material"));
    if (!bindings.empty()) return materialIndex(bindings.front().second, context);
    return defaultMaterial();
}

uint32_t Materials::materialIndex(const std::string& targetUrl, const std::string& context) {
    const pugi::xml_node material = m_document.resolve(targetUrl.c_str(), "material", context);
    const std::string id = material.attribute("id").as_string();
    if (const auto it = m_materialsById.find(id); it != m_materialsById.end()) return it->second;
    const uint32_t index = static_cast<uint32_t>(m_materials.size());
    Material m = readMaterial(material);
    m_materials.push_back(std::move(m));
    m_materialsById.emplace(id, index);
    return index;
}

Material Materials::readMaterial(pugi::xml_node material) {
    Material m;
    m.name = nameOf(material);
    const std::string what = fmt::format("material '{}'", m.name);
    const pugi::xml_node effect = m_document.resolve(
        material.child("instance_effect").attribute("url").as_string(nullptr), "effect", what);

    const pugi::xml_node cmu = cmuTechnique(effect);
    bool haveBsdf = false, haveEmission = false;
    for (pugi::xml_node bsdf : cmu.children()) {
        const std::string_view kind = bsdf.name();
        const std::string where = fmt::format("{}: CMU462 <{}>", what, kind);
        auto optionalColor = [&](const char* child, glm::vec3 fallback) {
            const pugi::xml_node e = bsdf.child(child);
            return e ? m_document.color(e, fmt::format("{} <{}>", where, child)) : fallback;
        };
        if (kind == "emission") {
            m.emission = m_document.color(bsdf.child("radiance"), where + " <radiance>");
            haveEmission = true;
        } else if (kind == "mirror") {
            m.kind = MaterialKind::Mirror;
            m.reflectance = optionalColor("reflectance", glm::vec3(1.0f));
            haveBsdf = true;
        } else if (kind == "glass" || kind == "refraction") {
            m.kind = MaterialKind::Dielectric;
            m.transmittance = optionalColor("transmittance", glm::vec3(1.0f));
            // Scotty3D's RefractionBSDF only transmits: no reflected tint.
            m.reflectance =
                kind == "glass" ? optionalColor("reflectance", glm::vec3(1.0f)) : glm::vec3(0.0f);
            if (kind == "refraction")
                m_warnings.addExample("refraction",
                                      fmt::format("{}: refraction-only BSDF approximated by glass "
                                                  "with zero reflectance",
                                                  what));
            if (const pugi::xml_node ior = bsdf.child("ior")) {
                const double value = m_document.scalar(ior, where + " <ior>");
                if (!(value > 0))
                    m_document.fail(fmt::format("{} <ior> {} is not positive", where, value));
                m.ior = static_cast<float>(value);
            } else {
                m_warnings.addExample("ior", fmt::format("{} has no <ior>; using 1.5", where));
            }
            // Scotty3D's glass never used its roughness; vkpath reads it as
            // glTF's perceptual roughness (GGX alpha = roughness^2) in [0, 1].
            if (const pugi::xml_node roughness = bsdf.child("roughness")) {
                const double value = m_document.scalar(roughness, where + " <roughness>");
                if (!(value >= 0.0 && value <= 1.0))
                    m_document.fail(
                        fmt::format("{} <roughness> {} is not in [0, 1]", where, value));
                if (value > 0.0) {
                    m.kind = MaterialKind::RoughDielectric;
                    m.roughness = static_cast<float>(value);
                }
            }
            haveBsdf = true;
        } else {
            m_warnings.addExample("cmu-bsdf",
                                  fmt::format("{}: unknown CMU462 BSDF <{}> ignored", what, kind));
        }
    }
    if (haveEmission && !haveBsdf) {
        // Scotty3D's EmissionBSDF emits and reflects nothing.
        m.reflectance = glm::vec3(0.0f);
        return m;
    }
    if (haveEmission)
        m_warnings.addExample("emission-bsdf",
                              fmt::format("{}: CMU462 <emission> together with a BSDF; vkpath "
                                          "keeps both (Scotty3D keeps the last)",
                                          what));
    if (haveBsdf) return m;

    // profile_COMMON: the shading model's <diffuse> colour is a Lambertian albedo.
    pugi::xml_node shading;
    for (pugi::xml_node technique : effect.child("profile_COMMON").children("technique"))
        for (const char* model : {"phong", "blinn", "lambert", "constant"})
            if (!shading) shading = technique.child(model);
    m.kind = MaterialKind::Diffuse;
    m.reflectance = glm::vec3(0.5f);
    if (const pugi::xml_node diffuse = shading.child("diffuse")) {
        if (diffuse.child("color")) {
            m.reflectance = m_document.color(diffuse.child("color"), what + " <diffuse><color>");
        } else if (const pugi::xml_node texture = diffuse.child("texture")) {
            m.baseColorTexture = m_textures.reference(texture, effect, what);
            if (m.baseColorTexture.present())
                m.reflectance = glm::vec3(1.0f);  // the texture is the albedo
        }
    }
    if (glm::any(glm::greaterThan(m.reflectance, glm::vec3(1.0f)))) {
        m_warnings.addExample("albedo", fmt::format("{}: diffuse albedo {} above 1 clamped", what,
                                                    vecString(m.reflectance)));
        m.reflectance = glm::min(m.reflectance, glm::vec3(1.0f));
    }
    if (const pugi::xml_node specular = shading.child("specular").child("color")) {
        const glm::vec3 s = m_document.color(specular, what + " <specular><color>");
        if (s != glm::vec3(0.0f))
            m_warnings.addExample("specular",
                                  fmt::format("{}: Phong/Blinn specular {} is not modelled; the "
                                              "surface is Lambertian in its diffuse colour (as in "
                                              "Scotty3D)",
                                              what, vecString(s)));
    }
    if (const pugi::xml_node emission = shading.child("emission").child("color")) {
        const glm::vec3 e = m_document.color(emission, what + " <emission><color>");
        if (e != glm::vec3(0.0f))
            m_warnings.addExample("common-emission",
                                  fmt::format("{}: profile_COMMON emission {} ignored (Scotty3D "
                                              "emits only through CMU462 <emission><radiance>)",
                                              what, vecString(e)));
    }
    if (shading.child("transparent") || shading.child("transparency"))
        m_warnings.addExample(
            "transparency",
            fmt::format("{}: transparency is not modelled; the surface is opaque", what));
    return m;
}

}  // namespace vkpath::scene::collada
