// What shading reads of a triangle besides its positions (which the BVH's
// primitives hold): the indices of its three vertices into the scene's vertex
// attribute arrays, and which attributes those vertices carry. Built on the
// host (host/wavefront/surface_tables) only for scenes that use an attribute;
// a scene without any gets placeholders and kernels without the code.
//
// Indexed by BvhPrimitive::id (triangles over all meshes in scene order), so
// the leaf order of the BVH does not matter. The vertex arrays hold the
// vertices of all meshes, mesh after mesh; an attribute array is either empty
// (no triangle uses it) or as long as the vertex list (vertices of meshes
// without the attribute hold zeros, and their triangles' bits say so).
#ifndef VKPATH_SHARED_MESH_ATTRIBUTES_H
#define VKPATH_SHARED_MESH_ATTRIBUTES_H

#include "shared/compat.h"
#include "shared/records.h"

// TriangleVertices::attributes
// Interpolate the vertex normals for shading. Set only where they differ from
// the face normal: a flat triangle shades with its geometric normal exactly.
#define VKP_TRIANGLE_SHADING_NORMALS 1u
// Its vertices have texture coordinates (TEXCOORD_0 and _1; missing sets are 0).
#define VKP_TRIANGLE_TEXCOORDS 2u
// Its vertices have colours (COLOR_0), which multiply the base colour.
#define VKP_TRIANGLE_COLORS 4u
// Its material has a normal map, and its vertices have tangents (TANGENT, or
// MikkTSpace's: host/scene/tangents.h) and the map's texture coordinates.
#define VKP_TRIANGLE_TANGENTS 8u

VKP_NAMESPACE_BEGIN

// TriangleVertices's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_TRIANGLE_VERTICES_FIELDS(F)                                                      \
    /* indices into the vertex attribute arrays, in the triangle's own order (p0, p1, p2) */ \
    F(uvec3, vertex, 0)                                                                      \
    /* VKP_TRIANGLE_* bits */                                                                \
    F(uint, attributes, 3)
struct TriangleVertices {
    VKP_TRIANGLE_VERTICES_FIELDS(VKP_FIELD_DECLARE)
};

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD TriangleVertices
VKP_RECORD_CHECK(VKP_TRIANGLE_VERTICES_FIELDS, 1)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_MESH_ATTRIBUTES_H
