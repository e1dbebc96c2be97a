#include "scene/scene.h"

#include <algorithm>
#include <limits>

namespace vkpath::scene {

Bounds Scene::geometryBounds() const {
    Bounds b{glm::vec3(std::numeric_limits<float>::max()),
             glm::vec3(-std::numeric_limits<float>::max())};
    for (const Mesh& m : meshes)
        for (const glm::uvec3& t : m.triangles)
            for (int k = 0; k < 3; ++k) {
                b.lo = glm::min(b.lo, m.positions[t[k]]);
                b.hi = glm::max(b.hi, m.positions[t[k]]);
            }
    for (const Sphere& s : spheres) {
        b.lo = glm::min(b.lo, s.center - s.radius);
        b.hi = glm::max(b.hi, s.center + s.radius);
    }
    return b;
}

size_t Scene::triangleCount() const {
    size_t count = 0;
    for (const Mesh& m : meshes) count += m.triangles.size();
    return count;
}

GeometryCounts Scene::countGeometry() const {
    GeometryCounts c;
    for (const Mesh& m : meshes) {
        c.triangles += m.triangles.size();
        c.vertices += m.positions.size();
        c.normals += m.normals.size();
        c.texcoords += std::max(m.texcoords0.size(), m.texcoords1.size());
        c.colors += m.colors.size();
        c.tangents += m.tangents.size();
    }
    c.spheres = spheres.size();
    return c;
}

FeatureSummary Scene::features() const {
    FeatureSummary f;
    auto useMaterial = [&](uint32_t index) {
        const Material& m = materials.at(index);
#define VKP_KIND_USED(id, NAME, Type, key, label, feature, flags, regularized) \
    f.key |= m.kind == MaterialKind::Type;
        VKP_MATERIAL_KINDS(VKP_KIND_USED)
#undef VKP_KIND_USED
        f.emissiveSurfaces |= m.emissive();
    };
    for (const Mesh& m : meshes) {
        if (m.triangles.empty()) continue;
        f.triangles = true;
        useMaterial(m.material);
    }
    for (const Sphere& s : spheres) {
        f.spheres = true;
        useMaterial(s.material);
    }
    f.pointLights = !pointLights.empty();
    f.spotLights = !spotLights.empty();
    f.directionalLights = !directionalLights.empty();
    f.environment = environment.has_value();
    return f;
}

}  // namespace vkpath::scene
