#include "scene/gltf_meshes.h"

#include <fmt/format.h>

#include <cmath>

#include "input_error.h"

namespace vkpath::scene::gltf {
namespace {

const char* modeName(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS:
            return "POINTS";
        case TINYGLTF_MODE_LINE:
            return "LINES";
        case TINYGLTF_MODE_LINE_LOOP:
            return "LINE_LOOP";
        case TINYGLTF_MODE_LINE_STRIP:
            return "LINE_STRIP";
        case TINYGLTF_MODE_TRIANGLES:
            return "TRIANGLES";
        case TINYGLTF_MODE_TRIANGLE_STRIP:
            return "TRIANGLE_STRIP";
        case TINYGLTF_MODE_TRIANGLE_FAN:
            return "TRIANGLE_FAN";
        default:
            return "unknown";
    }
}

// The vertex indices of `mode`'s primitives (in drawing order) as a
// triangle list: glTF 2.0, 3.7.2.1 "Topology Types". A strip's triangle i is
// (v_i, v_{i+1+i%2}, v_{i+2-i%2}), which keeps every second triangle's
// winding counter-clockwise; a fan's is (v_{i+1}, v_{i+2}, v_0). Strips and
// fans of fewer than three vertices draw nothing.
std::vector<uint32_t> triangleList(int mode, std::vector<uint32_t> vertices) {
    if (mode == TINYGLTF_MODE_TRIANGLES) return vertices;
    std::vector<uint32_t> list;
    for (size_t i = 0; i + 2 < vertices.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
            list.insert(list.end(),
                        {vertices[i], vertices[i + 1 + i % 2], vertices[i + 2 - i % 2]});
        else
            list.insert(list.end(), {vertices[i + 1], vertices[i + 2], vertices[0]});
    }
    return list;
}

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

template <typename... Args>
[[noreturn]] void fail(const std::string& file, fmt::format_string<Args...> format,
                       Args&&... args) {
    throw InputError(
        fmt::format("{}: {}", file, fmt::format(format, std::forward<Args>(args)...)));
}

}  // namespace

std::vector<WorldPrimitive> convertMesh(const tinygltf::Model& model, const Accessors& accessors,
                                        int nodeIndex, const std::string& nodeName,
                                        const glm::dmat4& world, const std::string& file,
                                        ImportWarnings& warnings) {
    const tinygltf::Node& node = model.nodes[size_t(nodeIndex)];
    if (size_t(node.mesh) >= model.meshes.size())
        fail(file, "{}: mesh {} does not exist", nodeName, node.mesh);
    const tinygltf::Mesh& mesh = model.meshes[size_t(node.mesh)];
    const glm::dmat3 linear(world);
    const double det = glm::determinant(linear);
    const bool flip = det < 0.0;  // a mirroring transform turns counter-clockwise into clockwise
    const bool singular = !(std::abs(det) > 0.0) || !std::isfinite(det);
    const glm::dmat3 normalMatrix =
        singular ? glm::dmat3(0.0) : glm::transpose(glm::inverse(linear));
    const std::string baseName =
        !node.name.empty() ? node.name
                           : (!mesh.name.empty() ? mesh.name : fmt::format("mesh {}", node.mesh));

    std::vector<WorldPrimitive> primitives;
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& primitive = mesh.primitives[p];
        Mesh out;
        out.name = mesh.primitives.size() == 1 ? baseName : fmt::format("{}#{}", baseName, p);
        const std::string what = fmt::format("mesh '{}'", out.name);
        if (primitive.mode != TINYGLTF_MODE_TRIANGLES &&
            primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN)
            fail(file,
                 "{}: primitive mode {} ({}) is not supported; only the triangle modes TRIANGLES "
                 "(4), TRIANGLE_STRIP (5) and TRIANGLE_FAN (6) are",
                 what, primitive.mode, modeName(primitive.mode));
        const auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end())
            fail(file, "{}: primitive has no POSITION", what);
        for (const auto& [attribute, accessor] : primitive.attributes) {
            if (attribute.rfind("COLOR_", 0) == 0)
                warnings.addCounted("vertex colours (COLOR_n) are ignored", "mesh", out.name);
            if (attribute.rfind("JOINTS_", 0) == 0 && node.skin < 0)
                warnings.addCounted("skins are ignored: meshes are used as bound", "mesh",
                                    out.name);
        }
        if (!primitive.targets.empty())
            warnings.addCounted("morph targets are ignored", "mesh", out.name);

        const std::vector<glm::vec3> local = accessors.vec3(position->second, what + " POSITION");
        out.positions.resize(local.size());
        for (size_t i = 0; i < local.size(); ++i) {
            const glm::dvec3 p3(world * glm::dvec4(glm::dvec3(local[i]), 1.0));
            if (!finite(p3) || !finite(glm::dvec3(glm::vec3(p3))))
                fail(file, "{}: position {} is not finite after the node transform", what, i);
            out.positions[i] = glm::vec3(p3);
        }

        if (const auto normal = primitive.attributes.find("NORMAL");
            normal != primitive.attributes.end()) {
            const std::vector<glm::vec3> normals =
                accessors.vec3(normal->second, what + " NORMAL");
            if (normals.size() != local.size())
                fail(file, "{}: {} normals for {} positions", what, normals.size(), local.size());
            out.normals.resize(normals.size());
            bool usable = !singular;
            for (size_t i = 0; i < normals.size() && usable; ++i) {
                const glm::dvec3 n = normalMatrix * glm::dvec3(normals[i]);
                const double length = glm::length(n);
                usable = length > 1e-12 && std::isfinite(length);
                out.normals[i] = glm::vec3(n / length);
            }
            if (!usable) {
                warnings.addCounted("zero-length normals: face normals are used instead", "mesh",
                                    out.name);
                out.normals.clear();
            }
        }

        std::vector<uint32_t> indices;
        if (primitive.indices >= 0) {
            indices = accessors.indices(primitive.indices, what + " indices");
        } else {
            indices.resize(local.size());
            for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
        }
        if (primitive.mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
            fail(file, "{}: {} {} is not a multiple of 3", what,
                 primitive.indices >= 0 ? "index count" : "vertex count", indices.size());
        indices = triangleList(primitive.mode, std::move(indices));
        size_t degenerate = 0;
        for (size_t t = 0; t < indices.size(); t += 3) {
            glm::uvec3 tri(indices[t], indices[t + 1], indices[t + 2]);
            for (int k = 0; k < 3; ++k)
                if (tri[k] >= local.size())
                    fail(file, "{}: index {} is out of range ({} vertices)", what, tri[k],
                         local.size());
            const glm::vec3 a = out.positions[tri.x], b = out.positions[tri.y],
                            c = out.positions[tri.z];
            const float area = glm::length(glm::cross(b - a, c - a));
            if (!(area > 0.0f) || !std::isfinite(area)) {
                ++degenerate;
                continue;
            }
            if (flip) std::swap(tri.y, tri.z);
            out.triangles.push_back(tri);
        }
        if (degenerate > 0)
            warnings.addCounted("degenerate triangles (zero area) are dropped", "triangle",
                                out.name, degenerate);
        if (out.triangles.empty()) continue;
        if (primitive.material >= 0) {
            if (size_t(primitive.material) >= model.materials.size())
                fail(file, "{}: material {} does not exist", what, primitive.material);
            out.material = uint32_t(primitive.material);  // glTF materials keep their indices
        }
        primitives.push_back({std::move(out), primitive.material < 0});
    }
    return primitives;
}

}  // namespace vkpath::scene::gltf
