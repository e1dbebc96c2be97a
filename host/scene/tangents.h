// Per-vertex tangent frames for tangent-space normal maps where a glTF mesh
// gives none: glTF 2.0 (section 3.7.2.1) asks for MikkTSpace's, so that a map
// baked against the modelling tool's frames reads back the same normals.
//
// MikkTSpace (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited",
// chapter 4, and the description accompanying its reference code), as
// written here from that description:
//   - each triangle's tangent is dP/ds, the surface's derivative along the
//     texture's first coordinate (from the two edges and their UV
//     differences, Mikkelsen's eq. 4.2), and its orientation is the sign of
//     the triangle's UV area: negative where the texture is mirrored;
//   - at each corner that tangent is projected into the plane of the
//     corner's normal (Gram-Schmidt), normalised, and weighted by the
//     corner's angle;
//   - a vertex is what shares position, normal and texture coordinates
//     (vertices equal in all three are one, whatever their indices), and the
//     corners of a vertex are summed per orientation: where mirrored and
//     unmirrored triangles meet, the vertex is split in two;
//   - the sum, made orthogonal to the normal again and normalised, is the
//     tangent; w = +1 or -1, the orientation, gives the bitangent
//     B = w (N x T) that glTF defines.
// MikkTSpace takes texture coordinates with v up (Blender's, where it was
// made), glTF's run down (the image's first row is v = 0): v is negated
// here, so that B points up the image, the direction of a normal map's +Y
// (glTF 2.0, section 3.9.3). Without it every w would be the opposite, the
// question of KhronosGroup/glTF-Sample-Models issue 174.
//
// Simplifications, which change nothing on meshes without degenerate
// triangles: the corners of one vertex and orientation form one group even
// where MikkTSpace would find two fans not connected through an edge; a
// triangle with a UV area of 0 (or positions in a line) adds nothing and
// takes the frame of its vertices' other triangles; a vertex with no usable
// triangle gets a unit tangent orthogonal to its normal (Duff et al. 2017)
// with w = +1, never NaN.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace vkpath::scene {

// A mesh's vertices as tangents split them. The first positions.size()
// vertices are the input's own, in order; vertices split off (a second
// orientation, or a second face normal on a mesh without normals) follow.
struct MeshTangents {
    std::vector<glm::vec4> tangents;     // per vertex: unit xyz, w = +-1 so that B = w (N x T)
    std::vector<uint32_t> sourceVertex;  // per vertex: the input vertex whose attributes it has
    std::vector<glm::uvec3> triangles;   // the input's triangles, in order, over these vertices
};

// The MikkTSpace-compatible tangents of a triangle mesh. `uvs` (glTF's
// convention, v down) must be per vertex; `normals` per vertex or empty (then
// each triangle's face normal is its corners' normal, as glTF has flat
// shading without NORMAL). Triangles whose indices are out of range are kept
// as they are and add nothing.
MeshTangents generateTangents(std::span<const glm::vec3> positions,
                              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
                              std::span<const glm::uvec3> triangles);

}  // namespace vkpath::scene
