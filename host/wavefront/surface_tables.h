// What shading reads of triangles besides their positions, flattened for the
// integrators (shared/mesh_attributes.h): per triangle the indices of its
// vertices and which attributes they carry, per vertex the attributes. Only
// attributes that change shading are kept: vertex normals of a triangle that
// equal its face normal are dropped (a flat mesh costs nothing), texture
// coordinates only where the mesh's material has a texture, colours only
// where some vertex of the mesh is not white, tangents only where its
// material has a normal map (the file's TANGENT, else MikkTSpace-compatible
// ones from host/scene/tangents, whose vertex splits the tables follow).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "scene/scene.h"
#include "shared/mesh_attributes.h"

namespace vkpath::wavefront {

struct SurfaceTables {
    // Both empty when no triangle has an attribute (`attributes` == 0).
    std::vector<shared::TriangleVertices> triangleVertices;  // by triangle id (BvhPrimitive::id)
    // World space, unit (w 0: one 16-byte texel); zero for vertices of meshes without normals.
    std::vector<glm::vec4> vertexNormals;
    std::vector<glm::vec4>
        vertexTexcoords;                  // (TEXCOORD_0, TEXCOORD_1); zero where a mesh lacks a set
    std::vector<glm::vec4> vertexColors;  // COLOR_0, linear RGBA
    std::vector<glm::vec4>
        vertexTangents;       // world space unit xyz, w = +-1 (B = w (N x T)); zero without a map
    uint32_t attributes = 0;  // VKP_TRIANGLE_* bits that some triangle has
};

// Vertex normals within this angle of the face normal (1 - cos) shade like it:
// 1e-6 is about 0.08 degrees, below what an image shows and above the
// rounding of normals stored as floats.
constexpr double FLAT_NORMAL_TOLERANCE = 1e-6;

// Whether the vertex normals n0, n1, n2 (unit) of the triangle p0 p1 p2 shade
// it as its face normal does: all within FLAT_NORMAL_TOLERANCE of it, on one
// side. Invalid normals (zero, non-finite) count as flat: there is nothing to
// interpolate.
bool isFlatShaded(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 n0, glm::vec3 n1,
                  glm::vec3 n2);

// The tables of `scene` (render space or world space alike: normals do not
// move with a translation).
SurfaceTables buildSurfaceTables(const scene::Scene& scene);

}  // namespace vkpath::wavefront
