// glTF meshes as world-space triangle meshes: primitive modes, attributes,
// indices and the node transform.
#pragma once

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene::gltf {

// One triangle primitive of a glTF mesh, in world space.
struct WorldPrimitive {
    Mesh mesh;  // mesh.material is the glTF material index unless usesDefaultMaterial
    bool usesDefaultMaterial = false;  // the primitive names no material
};

// The primitives of node `nodeIndex`'s mesh under the node's world transform,
// those left with no triangles omitted:
//   - TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN (glTF 2.0, 3.7.2.1) become
//     triangle lists; other modes are an error;
//   - normals go through the inverse transpose, tangents through the
//     transform with w negated under a mirror; a transform with a negative
//     determinant flips the winding so fronts stay counter-clockwise;
//   - TEXCOORD_0/1 and COLOR_0 are kept as stored (docs/SCENES.md has the
//     encodings each attribute may use, in core glTF and with
//     KHR_mesh_quantization);
//   - degenerate triangles are dropped with a warning.
// `nodeName` names the node in errors; errors name the file and the mesh.
std::vector<WorldPrimitive> convertMesh(const tinygltf::Model& model, const Accessors& accessors,
                                        int nodeIndex, const std::string& nodeName,
                                        const glm::dmat4& world, const std::string& file,
                                        ImportWarnings& warnings);

// What convertMesh makes of mesh `meshIndex` under one node, counted from its
// accessors' counts without reading them: an upper bound where degenerate
// triangles are dropped or unusable normals and tangents discarded. A
// primitive convertMesh would refuse counts what its accessors say, or
// nothing where they do not exist: convertMesh says what is wrong.
GeometryCounts countMesh(const tinygltf::Model& model, int meshIndex);

}  // namespace vkpath::scene::gltf
