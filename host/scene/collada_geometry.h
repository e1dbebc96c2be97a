// COLLADA geometry: <mesh> primitives read once per <geometry> in their own
// space, then instanced per node in world space (normals, winding, vertex
// splitting); and the CMU462 spheres.
#pragma once

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <limits>
#include <optional>
#include <pugixml.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "scene/collada_document.h"
#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene::collada {

constexpr uint32_t NO_INDEX = std::numeric_limits<uint32_t>::max();

// A corner of a triangle: an index into LocalMesh::positions, one into
// LocalMesh::normals and one into LocalMesh::texCoords (NO_INDEX when the
// primitive has no such input).
struct Corner {
    uint32_t position;
    uint32_t normal;
    uint32_t texCoord;
};

// One <polylist>/<triangles>/... of a <mesh>, triangulated, in file winding.
struct Primitive {
    std::string symbol;           // material symbol, bound per instance
    std::vector<Corner> corners;  // 3 per triangle
};

// A <geometry><mesh> in its own space, parsed once however often instanced.
struct LocalMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> texCoords;  // (u, 1 - v): glTF's top-left origin (scene.h)
    std::vector<Primitive> primitives;
    uint64_t degeneratePolygons = 0;  // fewer than 3 vertices
};

class Geometry {
  public:
    // `document` and `warnings` must outlive this.
    Geometry(const Document& document, ImportWarnings& warnings)
        : m_document(document), m_warnings(warnings) {}

    // The <mesh> of `geometry`, read on first use.
    const LocalMesh& localMesh(pugi::xml_node geometry);

    // Appends the world-space meshes of `local` under `world` (one per
    // primitive that keeps a triangle) to `meshes`; `materialFor` gives the
    // scene material of a primitive's material symbol.
    void addMeshInstance(const LocalMesh& local, const glm::dmat4& world,
                         const std::string& nodeName,
                         const std::function<uint32_t(const std::string&)>& materialFor,
                         std::vector<Mesh>& meshes);

    // A sphere of `radius` under `world` (material left to the caller), or
    // none with a warning when the transform collapses it.
    std::optional<Sphere> sphereInstance(double radius, const glm::dmat4& world,
                                         const std::string& nodeName);

    // Polygons and triangles dropped as degenerate, in all instances so far.
    uint64_t droppedTriangles() const { return m_droppedTriangles; }
    // Zero or non-finite corner normals replaced by their face's normal.
    uint64_t replacedNormals() const { return m_replacedNormals; }

  private:
    [[noreturn]] void fail(const std::string& what) const { m_document.fail(what); }
    std::vector<glm::vec3> readSource(pugi::xml_node source, size_t width,
                                      bool requireFinite) const;
    void readPrimitive(pugi::xml_node element, pugi::xml_node mesh, const std::string& geometryName,
                       LocalMesh& local);

    const Document& m_document;
    ImportWarnings& m_warnings;
    std::unordered_map<const void*, LocalMesh> m_localMeshes;  // by <geometry> element
    uint64_t m_triangles = 0;
    uint64_t m_droppedTriangles = 0;
    uint64_t m_replacedNormals = 0;
};

}  // namespace vkpath::scene::collada
