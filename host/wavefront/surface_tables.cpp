#include "wavefront/surface_tables.h"

#include <cmath>

#include "scene/tangents.h"
#include "wavefront/texture_tables.h"

namespace vkpath::wavefront {
namespace {

bool usable(const glm::vec3& n) {
    return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && glm::dot(n, n) > 0.0f;
}

}  // namespace

bool isFlatShaded(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 n0, glm::vec3 n1,
                  glm::vec3 n2) {
    if (!usable(n0) || !usable(n1) || !usable(n2)) return true;
    const glm::dvec3 face =
        glm::cross(glm::dvec3(p1) - glm::dvec3(p0), glm::dvec3(p2) - glm::dvec3(p0));
    const double area2 = glm::dot(face, face);
    if (!(area2 > 0.0) || !std::isfinite(area2)) return true;  // degenerate: never hit
    const glm::dvec3 unitFace = face / std::sqrt(area2);
    int side = 0;
    for (const glm::vec3& n : {n0, n1, n2}) {
        const double c = glm::dot(unitFace, glm::normalize(glm::dvec3(n)));
        if (std::abs(c) < 1.0 - FLAT_NORMAL_TOLERANCE) return false;
        const int s = c > 0 ? 1 : -1;
        if (side != 0 && s != side)
            return false;  // opposite normals would cancel when interpolated
        side = s;
    }
    return true;
}

namespace {

// The attribute bits the vertices of `mesh` carry for all its triangles.
uint32_t meshAttributes(const scene::Scene& scene, const scene::Mesh& mesh) {
    uint32_t bits = 0;
    const size_t n = mesh.positions.size();
    const bool hasTexcoords =
        (mesh.texcoords0.size() == n && n > 0) || (mesh.texcoords1.size() == n && n > 0);
    if (hasTexcoords && mesh.material < scene.materials.size() &&
        usesTextures(scene.materials[mesh.material]))
        bits |= VKP_TRIANGLE_TEXCOORDS;
    if (mesh.colors.size() == n)
        for (const glm::vec4& c : mesh.colors)
            if (c != glm::vec4(1.0f)) {
                bits |= VKP_TRIANGLE_COLORS;
                break;
            }
    return bits;
}

// A mesh's vertices as the tables hold them: its own, or as tangent
// generation split them, with tangents where its material has a normal map
// (its own or its clear coat's) or anisotropy.
struct MeshVertices {
    std::vector<uint32_t>
        source;  // per table vertex its mesh vertex; empty: the mesh's own, in order
    std::vector<glm::uvec3>
        triangles;  // the mesh's triangles over the table vertices; empty: its own
    std::vector<glm::vec4> tangents;  // per table vertex; empty: no tangent frame

    size_t count(const scene::Mesh& mesh) const {
        return source.empty() ? mesh.positions.size() : source.size();
    }
    uint32_t vertex(size_t i) const { return source.empty() ? uint32_t(i) : source[i]; }
};

MeshVertices meshVertices(const scene::Scene& scene, const scene::Mesh& mesh) {
    MeshVertices v;
    if (mesh.material >= scene.materials.size()) return v;
    const scene::Material& material = scene.materials[mesh.material];
    const bool anisotropic =
        material.anisotropy > 0.0f &&
        (scene::materialKindInfo(material.kind).flags & VKP_KIND_MICROFACET) != 0;
    const bool coatMapped = material.clearcoat > 0.0f && material.clearcoatNormalTexture.present();
    if (!material.normalTexture.present() && !anisotropic && !coatMapped) return v;
    // The frame follows the normal map's texture coordinates, else the coat's
    // normal map's, else the anisotropy texture's, else TEXCOORD_0.
    const scene::TextureRef& map = material.normalTexture.present() ? material.normalTexture
                                   : coatMapped ? material.clearcoatNormalTexture
                                                : material.anisotropyTexture;
    const size_t n = mesh.positions.size();
    const std::vector<glm::vec2>& uvs = map.texCoord == 0 ? mesh.texcoords0 : mesh.texcoords1;
    if (n == 0 || uvs.size() != n) return v;  // nothing to make the frame from
    // Tangents from the file, except without normals: glTF 2.0 (3.7.2.1)
    // has flat shading then, and the file's tangents are to be ignored.
    const bool hasNormals = mesh.normals.size() == n;
    if (hasNormals && mesh.tangents.size() == n) {
        v.tangents = mesh.tangents;
        return v;
    }
    scene::MeshTangents generated = scene::generateTangents(
        mesh.positions,
        hasNormals ? std::span<const glm::vec3>(mesh.normals) : std::span<const glm::vec3>(), uvs,
        mesh.triangles);
    v.tangents = std::move(generated.tangents);
    if (generated.sourceVertex.size() > n) {  // some vertices were split
        v.source = std::move(generated.sourceVertex);
        v.triangles = std::move(generated.triangles);
    }
    return v;
}

}  // namespace

SurfaceTables buildSurfaceTables(const scene::Scene& scene) {
    SurfaceTables t;
    size_t triangles = 0, vertices = 0;
    std::vector<MeshVertices> layouts;
    layouts.reserve(scene.meshes.size());
    for (const scene::Mesh& mesh : scene.meshes) {
        layouts.push_back(meshVertices(scene, mesh));
        triangles += mesh.triangles.size();
        vertices += layouts.back().count(mesh);
    }
    std::vector<shared::TriangleVertices> triangleVertices;
    triangleVertices.reserve(triangles);
    uint32_t firstVertex = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const scene::Mesh& mesh = scene.meshes[m];
        const MeshVertices& layout = layouts[m];
        const bool hasNormals =
            mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty();
        const uint32_t attributes =
            meshAttributes(scene, mesh) | (layout.tangents.empty() ? 0u : VKP_TRIANGLE_TANGENTS);
        for (size_t i = 0; i < mesh.triangles.size(); ++i) {
            const glm::uvec3& tri = mesh.triangles[i];
            shared::TriangleVertices v{};
            v.attributes = attributes;
            v.vertex =
                glm::uvec3(firstVertex) + (layout.triangles.empty() ? tri : layout.triangles[i]);
            const bool inRange = tri.x < mesh.positions.size() && tri.y < mesh.positions.size() &&
                                 tri.z < mesh.positions.size();
            if (hasNormals && inRange &&
                !isFlatShaded(mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z],
                              mesh.normals[tri.x], mesh.normals[tri.y], mesh.normals[tri.z]))
                v.attributes |= VKP_TRIANGLE_SHADING_NORMALS;
            t.attributes |= v.attributes;
            triangleVertices.push_back(v);
        }
        firstVertex += uint32_t(layout.count(mesh));
    }
    if (t.attributes == 0) return t;
    t.triangleVertices = std::move(triangleVertices);
    // Each array holds every mesh's table vertices, copied from their mesh vertices.
    auto fill = [&](auto& array, auto value) {
        array.reserve(vertices);
        for (size_t m = 0; m < scene.meshes.size(); ++m)
            for (size_t k = 0; k < layouts[m].count(scene.meshes[m]); ++k)
                array.push_back(value(scene.meshes[m], layouts[m], k, layouts[m].vertex(k)));
    };
    if (t.attributes & VKP_TRIANGLE_SHADING_NORMALS)
        fill(t.vertexNormals, [](const scene::Mesh& mesh, const MeshVertices&, size_t, uint32_t i) {
            const glm::vec3 n =
                mesh.normals.size() == mesh.positions.size() ? mesh.normals[i] : glm::vec3(0.0f);
            return glm::vec4(usable(n) ? glm::normalize(n) : glm::vec3(0.0f), 0.0f);
        });
    if (t.attributes & VKP_TRIANGLE_TEXCOORDS)
        fill(t.vertexTexcoords, [](const scene::Mesh& mesh, const MeshVertices&, size_t,
                                   uint32_t i) {
            const size_t n = mesh.positions.size();
            return glm::vec4(mesh.texcoords0.size() == n ? mesh.texcoords0[i] : glm::vec2(0.0f),
                             mesh.texcoords1.size() == n ? mesh.texcoords1[i] : glm::vec2(0.0f));
        });
    if (t.attributes & VKP_TRIANGLE_COLORS)
        fill(t.vertexColors, [](const scene::Mesh& mesh, const MeshVertices&, size_t, uint32_t i) {
            return mesh.colors.size() == mesh.positions.size() ? mesh.colors[i] : glm::vec4(1.0f);
        });
    if (t.attributes & VKP_TRIANGLE_TANGENTS)
        fill(t.vertexTangents,
             [](const scene::Mesh&, const MeshVertices& layout, size_t k, uint32_t) {
                 return layout.tangents.empty() ? glm::vec4(0.0f) : layout.tangents[k];
             });
    return t;
}

}  // namespace vkpath::wavefront
