#include "scene/scene.h"

namespace vkpath::scene {

size_t Scene::triangleCount() const {
    size_t count = 0;
    for (const Mesh& m : meshes) count += m.triangles.size();
    return count;
}

FeatureSummary Scene::features() const {
    FeatureSummary f;
    auto useMaterial = [&](uint32_t index) {
        const Material& m = materials.at(index);
        f.diffuse |= m.kind == MaterialKind::Diffuse;
        f.mirror |= m.kind == MaterialKind::Mirror;
        f.glass |= m.kind == MaterialKind::Dielectric;
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
