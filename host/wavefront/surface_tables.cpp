#include "wavefront/surface_tables.h"

#include <cmath>

#include "wavefront/texture_tables.h"

namespace vkpath::wavefront {
namespace {

bool usable(const glm::vec3& n) {
    return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && glm::dot(n, n) > 0.0f;
}

}  // namespace

bool isFlatShaded(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 n0, glm::vec3 n1, glm::vec3 n2) {
    if (!usable(n0) || !usable(n1) || !usable(n2)) return true;
    const glm::dvec3 face = glm::cross(glm::dvec3(p1) - glm::dvec3(p0), glm::dvec3(p2) - glm::dvec3(p0));
    const double area2 = glm::dot(face, face);
    if (!(area2 > 0.0) || !std::isfinite(area2)) return true;  // degenerate: never hit
    const glm::dvec3 unitFace = face / std::sqrt(area2);
    int side = 0;
    for (const glm::vec3& n : {n0, n1, n2}) {
        const double c = glm::dot(unitFace, glm::normalize(glm::dvec3(n)));
        if (std::abs(c) < 1.0 - FLAT_NORMAL_TOLERANCE) return false;
        const int s = c > 0 ? 1 : -1;
        if (side != 0 && s != side) return false;  // opposite normals would cancel when interpolated
        side = s;
    }
    return true;
}

namespace {

// The attribute bits the vertices of `mesh` carry for all its triangles.
uint32_t meshAttributes(const scene::Scene& scene, const scene::Mesh& mesh) {
    uint32_t bits = 0;
    const size_t n = mesh.positions.size();
    const bool hasTexcoords = (mesh.texcoords0.size() == n && n > 0) || (mesh.texcoords1.size() == n && n > 0);
    if (hasTexcoords && mesh.material < scene.materials.size() && usesTextures(scene.materials[mesh.material]))
        bits |= VKP_TRIANGLE_TEXCOORDS;
    if (mesh.colors.size() == n)
        for (const glm::vec4& c : mesh.colors)
            if (c != glm::vec4(1.0f)) {
                bits |= VKP_TRIANGLE_COLORS;
                break;
            }
    return bits;
}

}  // namespace

SurfaceTables buildSurfaceTables(const scene::Scene& scene) {
    SurfaceTables t;
    size_t triangles = 0, vertices = 0;
    for (const scene::Mesh& mesh : scene.meshes) {
        triangles += mesh.triangles.size();
        vertices += mesh.positions.size();
    }
    std::vector<shared::TriangleVertices> triangleVertices;
    triangleVertices.reserve(triangles);
    uint32_t firstVertex = 0;
    for (const scene::Mesh& mesh : scene.meshes) {
        const bool hasNormals = mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty();
        const uint32_t attributes = meshAttributes(scene, mesh);
        for (const glm::uvec3& tri : mesh.triangles) {
            shared::TriangleVertices v{};
            v.attributes = attributes;
            v.vertex = glm::uvec3(firstVertex) + tri;
            const bool inRange = tri.x < mesh.positions.size() && tri.y < mesh.positions.size() &&
                                 tri.z < mesh.positions.size();
            if (hasNormals && inRange &&
                !isFlatShaded(mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z],
                              mesh.normals[tri.x], mesh.normals[tri.y], mesh.normals[tri.z]))
                v.attributes |= VKP_TRIANGLE_SHADING_NORMALS;
            t.attributes |= v.attributes;
            triangleVertices.push_back(v);
        }
        firstVertex += uint32_t(mesh.positions.size());
    }
    if (t.attributes == 0) return t;
    t.triangleVertices = std::move(triangleVertices);
    if (t.attributes & VKP_TRIANGLE_SHADING_NORMALS) {
        t.vertexNormals.reserve(vertices);
        for (const scene::Mesh& mesh : scene.meshes) {
            const bool hasNormals = mesh.normals.size() == mesh.positions.size();
            for (size_t i = 0; i < mesh.positions.size(); ++i) {
                const glm::vec3 n = hasNormals ? mesh.normals[i] : glm::vec3(0.0f);
                t.vertexNormals.push_back(usable(n) ? glm::normalize(n) : glm::vec3(0.0f));
            }
        }
    }
    if (t.attributes & VKP_TRIANGLE_TEXCOORDS) {
        t.vertexTexcoords.reserve(vertices);
        for (const scene::Mesh& mesh : scene.meshes) {
            const size_t n = mesh.positions.size();
            for (size_t i = 0; i < n; ++i)
                t.vertexTexcoords.emplace_back(mesh.texcoords0.size() == n ? mesh.texcoords0[i] : glm::vec2(0.0f),
                                               mesh.texcoords1.size() == n ? mesh.texcoords1[i] : glm::vec2(0.0f));
        }
    }
    if (t.attributes & VKP_TRIANGLE_COLORS) {
        t.vertexColors.reserve(vertices);
        for (const scene::Mesh& mesh : scene.meshes) {
            const size_t n = mesh.positions.size();
            for (size_t i = 0; i < n; ++i) t.vertexColors.push_back(mesh.colors.size() == n ? mesh.colors[i] : glm::vec4(1));
        }
    }
    return t;
}

}  // namespace vkpath::wavefront
