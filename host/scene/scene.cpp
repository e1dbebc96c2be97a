#include "scene/scene.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace vkpath::scene {

namespace {

Bounds emptyBounds() {
    return {glm::vec3(std::numeric_limits<float>::max()),
            glm::vec3(-std::numeric_limits<float>::max())};
}

Bounds meshBounds(const Mesh& m) {
    Bounds b = emptyBounds();
    for (const glm::uvec3& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            b.lo = glm::min(b.lo, m.positions[t[k]]);
            b.hi = glm::max(b.hi, m.positions[t[k]]);
        }
    return b;
}

}  // namespace

Bounds Scene::geometryBounds() const {
    Bounds b = emptyBounds();
    std::vector<Bounds> instancedBounds(meshes.size(), emptyBounds());
    for (size_t i = 0; i < meshes.size(); ++i) {
        const Bounds mb = meshBounds(meshes[i]);
        if (meshes[i].instanced) {
            instancedBounds[i] = mb;
            continue;
        }
        b.lo = glm::min(b.lo, mb.lo);
        b.hi = glm::max(b.hi, mb.hi);
    }
    // An instance's box: the corners of its meshes' box, placed.
    for (const Instance& instance : instances) {
        Bounds object = emptyBounds();
        for (uint32_t i = instance.firstMesh; i < instance.firstMesh + instance.meshCount; ++i) {
            object.lo = glm::min(object.lo, instancedBounds.at(i).lo);
            object.hi = glm::max(object.hi, instancedBounds.at(i).hi);
        }
        if (!(object.lo.x <= object.hi.x)) continue;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p((corner & 1) ? object.hi.x : object.lo.x,
                               (corner & 2) ? object.hi.y : object.lo.y,
                               (corner & 4) ? object.hi.z : object.lo.z);
            const glm::vec3 w(glm::dvec3(instance.objectToWorld * glm::dvec4(p, 1.0)));
            b.lo = glm::min(b.lo, w);
            b.hi = glm::max(b.hi, w);
        }
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

uint64_t Scene::drawnTriangleCount() const {
    uint64_t count = 0;
    for (const Mesh& m : meshes)
        if (!m.instanced) count += m.triangles.size();
    for (const Instance& instance : instances)
        for (uint32_t i = instance.firstMesh; i < instance.firstMesh + instance.meshCount; ++i)
            count += meshes.at(i).triangles.size();
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
    c.instances = instances.size();
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
