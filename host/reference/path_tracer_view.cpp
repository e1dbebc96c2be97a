#include "reference/path_tracer_view.h"

#include <fmt/format.h>

#include <stdexcept>

namespace vkpath::shared {

PathTracerView::PathTracerView(const wavefront::SceneTables& tables, const SceneInfo& info)
    : BvhView{tables.bvh.nodes, tables.bvh.primitives},
      m_info(info),
      m_materials(tables.materials),
      m_lights(tables.lights),
      m_lightAlias(tables.lightAlias),
      m_primitiveLight(tables.primitiveLight),
      m_envAlias(tables.envAlias),
      m_envRadiance(tables.envRadiance) {
    auto require = [](bool ok, const std::string& what) {
        if (!ok) throw std::invalid_argument("scene tables: " + what);
    };
    require(!nodes.empty(), "no BVH root node");
    for (const BvhPrimitive& p : primitives)
        require(p.material < m_materials.size(), fmt::format("material {} of {}", p.material, m_materials.size()));
    require(m_lights.size() == info.lightCount && m_lightAlias.size() == info.lightCount,
            fmt::format("{} lights and {} alias entries for lightCount {}", m_lights.size(), m_lightAlias.size(),
                        info.lightCount));
    require(m_primitiveLight.empty() || m_primitiveLight.size() == primitives.size(),
            fmt::format("{} primitive-light entries for {} primitives", m_primitiveLight.size(), primitives.size()));
    require(info.environmentLight == VKP_NO_LIGHT || info.environmentLight < info.lightCount,
            "environment light index out of range");
    if (info.hasEnvironment != 0u && info.environment.width > 0) {
        const size_t texels = size_t(info.environment.width) * info.environment.height;
        require(m_envRadiance.size() == texels, fmt::format("{} environment texels, expected {}",
                                                            m_envRadiance.size(), texels));
        require(info.environmentLight == VKP_NO_LIGHT || m_envAlias.size() == texels,
                fmt::format("{} environment alias entries, expected {}", m_envAlias.size(), texels));
    }
}

}  // namespace vkpath::shared
