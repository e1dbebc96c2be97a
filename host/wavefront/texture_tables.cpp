#include "wavefront/texture_tables.h"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <utility>

#include "input_error.h"

namespace vkpath::wavefront {

double srgbToLinear(double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

bool usesTextures(const scene::Material& m) {
    return m.baseColorTexture.present() || m.emissiveTexture.present() ||
           m.metallicRoughnessTexture.present() || m.normalTexture.present() ||
           m.clearcoatTexture.present() || m.clearcoatRoughnessTexture.present() ||
           m.clearcoatNormalTexture.present() || m.sheenColorTexture.present() ||
           m.sheenRoughnessTexture.present() || m.diffuseTransmissionTexture.present() ||
           m.diffuseTransmissionColorTexture.present() || m.iridescenceTexture.present() ||
           m.iridescenceThicknessTexture.present() || m.anisotropyTexture.present();
}

namespace {

// KHR_texture_transform: uv' = T R S uv with R = [cos sin; -sin cos] (the
// extension's matrix, which turns uv counter-clockwise in glTF's y-down
// texture space).
void setTransform(shared::TextureSlot& slot, const scene::TextureRef& ref) {
    const float c = std::cos(ref.rotation), s = std::sin(ref.rotation);
    slot.transformU = glm::vec3(c * ref.scale.x, s * ref.scale.y, ref.offset.x);
    slot.transformV = glm::vec3(-s * ref.scale.x, c * ref.scale.y, ref.offset.y);
}

class Builder {
  public:
    explicit Builder(const scene::Scene& scene) : m_scene(scene) {}

    TextureTables build() {
        m_tables.materialSlots.assign(m_scene.materials.size(), VKP_NO_TEXTURE);
        for (size_t i = 0; i < m_scene.materials.size(); ++i) {
            const scene::Material& m = m_scene.materials[i];
            if (!usesTextures(m)) continue;
            const uint32_t first = uint32_t(m_tables.slots.size());
            m_tables.slots.resize(first + VKP_SLOTS_PER_MATERIAL, emptySlot());
            m_tables.slots[first + VKP_SLOT_BASE_COLOR] = slot(m.baseColorTexture, true, m.name);
            m_tables.slots[first + VKP_SLOT_EMISSIVE] = slot(m.emissiveTexture, true, m.name);
            m_tables.slots[first + VKP_SLOT_METALLIC_ROUGHNESS] =
                slot(m.metallicRoughnessTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_NORMAL] = slot(m.normalTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_NORMAL].scale = m.normalScale;
            m_tables.slots[first + VKP_SLOT_CLEARCOAT] = slot(m.clearcoatTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_CLEARCOAT_ROUGHNESS] =
                slot(m.clearcoatRoughnessTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_CLEARCOAT_NORMAL] =
                slot(m.clearcoatNormalTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_CLEARCOAT_NORMAL].scale = m.clearcoatNormalScale;
            m_tables.slots[first + VKP_SLOT_SHEEN_COLOR] = slot(m.sheenColorTexture, true, m.name);
            m_tables.slots[first + VKP_SLOT_SHEEN_ROUGHNESS] =
                slot(m.sheenRoughnessTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_DIFFUSE_TRANSMISSION] =
                slot(m.diffuseTransmissionTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_DIFFUSE_TRANSMISSION_COLOR] =
                slot(m.diffuseTransmissionColorTexture, true, m.name);
            m_tables.slots[first + VKP_SLOT_IRIDESCENCE] =
                slot(m.iridescenceTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_IRIDESCENCE_THICKNESS] =
                slot(m.iridescenceThicknessTexture, false, m.name);
            m_tables.slots[first + VKP_SLOT_ANISOTROPY] = slot(m.anisotropyTexture, false, m.name);
            m_tables.materialSlots[i] = first;
        }
        return std::move(m_tables);
    }

  private:
    static shared::TextureSlot emptySlot() {
        shared::TextureSlot s{};
        s.texture = VKP_NO_TEXTURE;
        s.transformU = glm::vec3(1, 0, 0);
        s.transformV = glm::vec3(0, 1, 0);
        s.scale = 1.0f;
        return s;
    }

    shared::TextureSlot slot(const scene::TextureRef& ref, bool srgb, const std::string& material) {
        shared::TextureSlot s = emptySlot();
        if (!ref.present()) return s;
        if (size_t(ref.texture) >= m_scene.textures.size())
            throw InputError(fmt::format("material '{}': texture {} of {}", material, ref.texture,
                                         m_scene.textures.size()));
        s.texture = textureRecord(uint32_t(ref.texture), srgb);
        s.texCoord = ref.texCoord;
        setTransform(s, ref);
        return s;
    }

    uint32_t textureRecord(uint32_t texture, bool srgb) {
        const auto key = std::make_pair(texture, srgb);
        if (const auto it = m_records.find(key); it != m_records.end()) return it->second;
        const scene::Texture& t = m_scene.textures[texture];
        if (t.image >= m_scene.images.size())
            throw InputError(
                fmt::format("texture {}: image {} of {}", texture, t.image, m_scene.images.size()));
        const scene::TextureImage& image = m_scene.images[t.image];
        shared::TextureInfo info{};
        info.firstTexel = storedImage(t.image, srgb);
        info.width = image.width;
        info.height = image.height;
        info.sampling =
            uint32_t(t.wrapU) | uint32_t(t.wrapV) << 2 | (t.nearest ? VKP_TEXTURE_NEAREST : 0u);
        m_records[key] = uint32_t(m_tables.textures.size());
        m_tables.textures.push_back(info);
        return m_records[key];
    }

    // The image's texels decoded (sRGB colour or linear) in the store: where they start.
    uint32_t storedImage(uint32_t index, bool srgb) {
        const auto key = std::make_pair(index, srgb);
        if (const auto it = m_images.find(key); it != m_images.end()) return it->second;
        const scene::TextureImage& image = m_scene.images[index];
        if (image.width == 0 || image.height == 0 ||
            image.texels.size() != size_t(image.width) * image.height)
            throw InputError(fmt::format("image '{}': {} texels for {}x{}", image.name,
                                         image.texels.size(), image.width, image.height));
        const uint64_t first = m_tables.texels.size();
        if (first + image.texels.size() > UINT32_MAX)
            throw InputError(
                fmt::format("image '{}': the scene's textures pass 2^32 texels", image.name));
        // 65536 entries: each 16-bit value decoded once.
        std::vector<float> decode(65536);
        for (uint32_t v = 0; v < decode.size(); ++v)
            decode[v] = float(srgb ? srgbToLinear(v / 65535.0) : v / 65535.0);
        m_tables.texels.reserve(first + image.texels.size());
        for (const glm::u16vec4& t : image.texels)
            m_tables.texels.emplace_back(glm::packHalf2x16(glm::vec2(decode[t.x], decode[t.y])),
                                         glm::packHalf2x16(glm::vec2(decode[t.z], t.w / 65535.0f)));
        m_images[key] = uint32_t(first);
        return uint32_t(first);
    }

    const scene::Scene& m_scene;
    TextureTables m_tables;
    std::map<std::pair<uint32_t, bool>, uint32_t> m_records;  // (texture, sRGB) -> TextureInfo
    std::map<std::pair<uint32_t, bool>, uint32_t> m_images;   // (image, sRGB) -> first texel
};

}  // namespace

TextureTables buildTextureTables(const scene::Scene& scene) {
    return Builder(scene).build();
}

}  // namespace vkpath::wavefront
