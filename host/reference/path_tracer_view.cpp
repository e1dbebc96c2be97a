#include "reference/path_tracer_view.h"

#include <fmt/format.h>

#include <stdexcept>

namespace vkpath::shared {

SceneTablesView::SceneTablesView(const wavefront::SceneTables& tables, const SceneInfo& info)
    : m_primitives(tables.bvh.primitives),
      m_nodes(tables.bvh.traversalNodes),
      m_wide(bvh::collapseBvh(tables.bvh)),
      m_info(info),
#define VKP_ARRAY_SPAN_INIT(index, name, Record, access, member) m_##name(tables.member),
      VKP_SCENE_ARRAYS(VKP_ARRAY_SPAN_INIT)
#undef VKP_ARRAY_SPAN_INIT
          m_guideSpheres(tables.guideSpheres) {
    auto require = [](bool ok, const std::string& what) {
        if (!ok) throw std::invalid_argument("scene tables: " + what);
    };
    require(!tables.bvh.nodes.empty(), "no BVH root node");
    require(info.guideSphereCount <= m_guideSpheres.size() &&
                info.guideSphereCount <= VKP_MAX_GUIDE_SPHERES,
            fmt::format("{} guide spheres for guideSphereCount {}", m_guideSpheres.size(),
                        info.guideSphereCount));
    for (const BvhPrimitive& p : m_primitives)
        require(p.kind == VKP_PRIMITIVE_INSTANCE || p.material < m_materials.size(),
                fmt::format("material {} of {}", p.material, m_materials.size()));
    // With a tree, the alias table's second part: the tree, then each light after its range.
    const size_t aliasEntries =
        info.lightCount +
        (tables.lightTree.nodes.empty() ? 0 : 1 + info.lightCount - tables.lightTree.trails.size());
    require(m_lights.size() == info.lightCount && m_lightAlias.size() == aliasEntries,
            fmt::format("{} lights and {} alias entries for lightCount {}", m_lights.size(),
                        m_lightAlias.size(), info.lightCount));
    require(info.treeLights == 0u || (info.treeLights == m_lightTreeTrail.size() &&
                                      info.treeLights <= info.lightCount && !m_lightTree.empty()),
            fmt::format("treeLights {} with {} trails and {} tree nodes", info.treeLights,
                        m_lightTreeTrail.size(), m_lightTree.size()));
    for (const LightTreeNode& n : m_lightTree)
        require((n.flags & VKP_LIGHT_NODE_LEAF) != 0u ? n.index < m_lightTreeTrail.size()
                                                      : n.index < m_lightTree.size(),
                fmt::format("light tree node index {} out of range", n.index));
    require(m_primitiveLight.empty() || m_primitiveLight.size() == m_primitives.size(),
            fmt::format("{} primitive-light entries for {} primitives", m_primitiveLight.size(),
                        m_primitives.size()));
    if (info.triangleAttributes != 0u) {
        for (const BvhPrimitive& p : m_primitives)
            require(p.kind != VKP_PRIMITIVE_TRIANGLE || p.id < m_triangleVertices.size(),
                    fmt::format("triangle {} of {} with vertex attributes", p.id,
                                m_triangleVertices.size()));
        for (const TriangleVertices& t : m_triangleVertices)
            for (const auto& [bit, size] :
                 {std::pair{VKP_TRIANGLE_SHADING_NORMALS, m_vertexNormals.size()},
                  std::pair{VKP_TRIANGLE_TEXCOORDS, m_vertexTexcoords.size()},
                  std::pair{VKP_TRIANGLE_COLORS, m_vertexColors.size()},
                  std::pair{VKP_TRIANGLE_TANGENTS, m_vertexTangents.size()}})
                require((t.attributes & bit) == 0u ||
                            glm::all(glm::lessThan(t.vertex, glm::uvec3(uint(size)))),
                        "vertex attribute index out of range");
    }
    for (const Material& m : m_materials)
        require(m.textures == VKP_NO_TEXTURE ||
                    m.textures + VKP_SLOTS_PER_MATERIAL <= m_textureSlots.size(),
                "material texture slots out of range");
    require(info.alphaTested == 0u || m_materialAlpha.size() == m_materials.size(),
            fmt::format("{} alpha records for {} materials", m_materialAlpha.size(),
                        m_materials.size()));
    for (const MaterialAlpha& a : m_materialAlpha)
        require(a.baseColorSlot == VKP_NO_TEXTURE || a.baseColorSlot < m_textureSlots.size(),
                "alpha texture slot out of range");
    for (const TextureSlot& slot : m_textureSlots)
        require(slot.texture == VKP_NO_TEXTURE || slot.texture < m_textures.size(),
                "texture index out of range");
    for (const TextureInfo& t : m_textures)
        require(t.width > 0 && t.height > 0 &&
                    uint64_t(t.firstTexel) + uint64_t(t.width) * t.height <= m_texels.size(),
                "texture texels out of range");
    require(info.microfacetCompensation == 0u || m_microfacetAlbedo.size() == VKP_ALBEDO_TABLE_SIZE,
            fmt::format("{} microfacet albedo entries, expected {}", m_microfacetAlbedo.size(),
                        VKP_ALBEDO_TABLE_SIZE));
    require(info.environmentLight == VKP_NO_LIGHT || info.environmentLight < info.lightCount,
            "environment light index out of range");
    if (info.hasEnvironment != 0u && info.environment.width > 0) {
        const size_t texels = size_t(info.environment.width) * info.environment.height;
        require(m_envRadiance.size() == texels,
                fmt::format("{} environment texels, expected {}", m_envRadiance.size(), texels));
        require(
            info.environmentLight == VKP_NO_LIGHT || m_envAlias.size() == texels,
            fmt::format("{} environment alias entries, expected {}", m_envAlias.size(), texels));
    }
}

}  // namespace vkpath::shared
