#include "wavefront/alpha_tables.h"

#include <algorithm>

namespace vkpath::wavefront {
namespace {

// The smallest alpha the base-colour texture of `m` holds (1 without one).
// Bilinear filtering blends texels, so it never goes below their minimum.
float smallestTextureAlpha(const scene::Scene& scene, const scene::Material& m) {
    if (!m.baseColorTexture.present()) return 1.0f;
    const scene::Texture& texture = scene.textures.at(size_t(m.baseColorTexture.texture));
    const scene::TextureImage& image = scene.images.at(texture.image);
    uint16_t smallest = 65535;
    for (const glm::u16vec4& t : image.texels) smallest = std::min(smallest, t.w);
    return float(smallest) / 65535.0f;
}

}  // namespace

std::vector<shared::MaterialAlpha> buildMaterialAlpha(const scene::Scene& scene,
                                                      const TextureTables& textures) {
    // The smallest COLOR_0 alpha of the meshes of each material (1 without colours).
    std::vector<float> smallestVertexAlpha(scene.materials.size(), 1.0f);
    std::vector<bool> onTriangles(scene.materials.size(), false);
    for (const scene::Mesh& mesh : scene.meshes) {
        if (mesh.material >= scene.materials.size() || mesh.triangles.empty()) continue;
        onTriangles[mesh.material] = true;
        if (mesh.colors.size() != mesh.positions.size())
            continue;  // no COLOR_0 (surface_tables: white)
        for (const glm::vec4& c : mesh.colors)
            smallestVertexAlpha[mesh.material] = std::min(smallestVertexAlpha[mesh.material], c.w);
    }
    std::vector<shared::MaterialAlpha> table;
    bool tested = false;
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const scene::Material& m = scene.materials[i];
        shared::MaterialAlpha a{};
        a.mode = VKP_ALPHA_OPAQUE;
        a.cutoff = m.alphaCutoff;
        a.alpha = m.alpha;
        a.baseColorSlot = VKP_NO_TEXTURE;
        if (m.baseColorTexture.present() && textures.materialSlots.at(i) != VKP_NO_TEXTURE)
            a.baseColorSlot = textures.materialSlots[i] + VKP_SLOT_BASE_COLOR;
        if (m.alphaMode != scene::AlphaMode::Opaque && onTriangles[i]) {
            const float smallest =
                m.alpha * smallestTextureAlpha(scene, m) * smallestVertexAlpha[i];
            const float covers = m.alphaMode == scene::AlphaMode::Mask ? m.alphaCutoff : 1.0f;
            if (smallest < covers) {
                a.mode = uint32_t(m.alphaMode);
                tested = true;
            }
        }
        table.push_back(a);
    }
    if (!tested) table.clear();
    return table;
}

}  // namespace vkpath::wavefront
