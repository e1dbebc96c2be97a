#include "scene/gltf_meshes.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

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
    throw InputError(fmt::format("{}: {}", file, fmt::format(format, std::forward<Args>(args)...)));
}

// ---- attribute formats ------------------------------------------------------

constexpr int VEC2 = TINYGLTF_TYPE_VEC2, VEC3 = TINYGLTF_TYPE_VEC3, VEC4 = TINYGLTF_TYPE_VEC4;
constexpr Encoding F32{TINYGLTF_COMPONENT_TYPE_FLOAT, false};
constexpr Encoding I8{TINYGLTF_COMPONENT_TYPE_BYTE, false};
constexpr Encoding I8N{TINYGLTF_COMPONENT_TYPE_BYTE, true};
constexpr Encoding U8{TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, false};
constexpr Encoding U8N{TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, true};
constexpr Encoding I16{TINYGLTF_COMPONENT_TYPE_SHORT, false};
constexpr Encoding I16N{TINYGLTF_COMPONENT_TYPE_SHORT, true};
constexpr Encoding U16{TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, false};
constexpr Encoding U16N{TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, true};

// An attribute's formats in core glTF 2.0 (3.7.2.1, the attribute table) and
// with KHR_mesh_quantization (its table: integer positions and texture
// coordinates, normalized signed normals and tangents).
struct AttributeFormats {
    AttributeFormat core, quantized;
};

const AttributeFormats POSITION_FORMATS = {{{VEC3}, {F32}},
                                           {{VEC3}, {F32, I8, I8N, U8, U8N, I16, I16N, U16, U16N}}};
const AttributeFormats NORMAL_FORMATS = {{{VEC3}, {F32}}, {{VEC3}, {F32, I8N, I16N}}};
const AttributeFormats TANGENT_FORMATS = {{{VEC4}, {F32}}, {{VEC4}, {F32, I8N, I16N}}};
const AttributeFormats TEXCOORD_FORMATS = {{{VEC2}, {F32, U8N, U16N}},
                                           {{VEC2}, {F32, I8, I8N, U8, U8N, I16, I16N, U16, U16N}}};
const AttributeFormats COLOR_FORMATS = {{{VEC3, VEC4}, {F32, U8N, U16N}},
                                        {{VEC3, VEC4}, {F32, U8N, U16N}}};

bool allows(const AttributeFormat& format, const Encoding& encoding) {
    return std::find(format.encodings.begin(), format.encodings.end(), encoding) !=
           format.encodings.end();
}

// Reads a primitive's attributes, each checked against its formats and counted
// against POSITION.
class AttributeReader {
  public:
    AttributeReader(const tinygltf::Primitive& primitive, const Accessors& accessors,
                    const std::string& file, const std::string& meshName, bool quantized)
        : m_primitive(primitive),
          m_accessors(accessors),
          m_file(file),
          m_what(fmt::format("mesh '{}'", meshName)),
          m_quantized(quantized) {}

    const std::string& what() const { return m_what; }

    // Attribute `name` as floats (see Accessors::floats), or none when the
    // primitive lacks it; `count` elements unless `count` is 0.
    std::optional<std::vector<glm::vec4>> read(const std::string& name,
                                               const AttributeFormats& formats, size_t count,
                                               size_t& components) const {
        const auto it = m_primitive.attributes.find(name);
        if (it == m_primitive.attributes.end()) return std::nullopt;
        const std::string what = m_what + " " + name;
        if (!m_quantized) {
            const Encoding encoding = m_accessors.encoding(it->second, what);
            if (!allows(formats.core, encoding) && allows(formats.quantized, encoding))
                fail(m_file,
                     "{}: accessor {} must be {}, not {} (KHR_mesh_quantization allows it, but "
                     "the file does not use that extension)",
                     what, it->second, formatName(formats.core), encodingName(encoding));
        }
        std::vector<glm::vec4> values = m_accessors.floats(
            it->second, what, m_quantized ? formats.quantized : formats.core, components);
        if (count != 0 && values.size() != count)
            fail(m_file, "{}: {} elements for {} positions", what, values.size(), count);
        return values;
    }

  private:
    const tinygltf::Primitive& m_primitive;
    const Accessors& m_accessors;
    const std::string& m_file;
    std::string m_what;
    bool m_quantized;
};

}  // namespace

GeometryCounts countMesh(const tinygltf::Model& model, int meshIndex) {
    GeometryCounts counts;
    if (meshIndex < 0 || size_t(meshIndex) >= model.meshes.size()) return counts;
    auto accessorCount = [&](int accessor) -> uint64_t {
        return accessor >= 0 && size_t(accessor) < model.accessors.size()
                   ? model.accessors[size_t(accessor)].count
                   : 0;
    };
    for (const tinygltf::Primitive& primitive : model.meshes[size_t(meshIndex)].primitives) {
        const auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end()) continue;
        const uint64_t vertices = accessorCount(position->second);
        const uint64_t corners =
            primitive.indices >= 0 ? accessorCount(primitive.indices) : vertices;
        uint64_t triangles = 0;
        if (primitive.mode == TINYGLTF_MODE_TRIANGLES)
            triangles = corners / 3;
        else if (primitive.mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
                 primitive.mode == TINYGLTF_MODE_TRIANGLE_FAN)
            triangles = corners >= 3 ? corners - 2 : 0;
        if (triangles == 0) continue;  // omitted from the scene, or refused by convertMesh
        auto has = [&](const char* name) { return primitive.attributes.contains(name); };
        counts.triangles += triangles;
        counts.vertices += vertices;
        if (has("NORMAL")) counts.normals += vertices;
        if (has("TEXCOORD_0") || has("TEXCOORD_1")) counts.texcoords += vertices;
        if (has("COLOR_0")) counts.colors += vertices;
        if (has("TANGENT")) counts.tangents += vertices;
    }
    return counts;
}

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
    // KHR_mesh_quantization must be declared to be used (its spec: in
    // extensionsRequired); extensionsUsed is enough to read it here.
    const bool quantized =
        std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(),
                  "KHR_mesh_quantization") != model.extensionsUsed.end() ||
        std::find(model.extensionsRequired.begin(), model.extensionsRequired.end(),
                  "KHR_mesh_quantization") != model.extensionsRequired.end();

    std::vector<WorldPrimitive> primitives;
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& primitive = mesh.primitives[p];
        Mesh out;
        out.name = mesh.primitives.size() == 1 ? baseName : fmt::format("{}#{}", baseName, p);
        const AttributeReader attributes(primitive, accessors, file, out.name, quantized);
        const std::string& what = attributes.what();
        if (primitive.mode != TINYGLTF_MODE_TRIANGLES &&
            primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN)
            fail(file,
                 "{}: primitive mode {} ({}) is not supported; only the triangle modes TRIANGLES "
                 "(4), TRIANGLE_STRIP (5) and TRIANGLE_FAN (6) are",
                 what, primitive.mode, modeName(primitive.mode));
        if (!primitive.attributes.contains("POSITION"))
            fail(file, "{}: primitive has no POSITION", what);
        for (const auto& [attribute, accessor] : primitive.attributes) {
            if (attribute.rfind("COLOR_", 0) == 0 && attribute != "COLOR_0")
                warnings.addCounted("vertex colours other than COLOR_0 are ignored", "mesh",
                                    out.name);
            if (attribute.rfind("TEXCOORD_", 0) == 0 && attribute != "TEXCOORD_0" &&
                attribute != "TEXCOORD_1")
                warnings.addCounted("texture coordinates beyond TEXCOORD_1 are ignored", "mesh",
                                    out.name);
            if (attribute.rfind("JOINTS_", 0) == 0 && node.skin < 0)
                warnings.addCounted("skins are ignored: meshes are used as bound", "mesh",
                                    out.name);
        }
        if (!primitive.targets.empty())
            warnings.addCounted("morph targets are ignored", "mesh", out.name);

        // ---- positions and normals: world space --------------------------------
        size_t components = 0;
        const std::vector<glm::vec4> local =
            *attributes.read("POSITION", POSITION_FORMATS, 0, components);
        const size_t count = local.size();
        out.positions.resize(count);
        for (size_t i = 0; i < count; ++i) {
            const glm::dvec3 p3(world * glm::dvec4(glm::dvec3(glm::vec3(local[i])), 1.0));
            if (!finite(p3) || !finite(glm::dvec3(glm::vec3(p3))))
                fail(file, "{}: position {} is not finite after the node transform", what, i);
            out.positions[i] = glm::vec3(p3);
        }

        if (const auto normals = attributes.read("NORMAL", NORMAL_FORMATS, count, components)) {
            out.normals.resize(count);
            bool usable = !singular;
            for (size_t i = 0; i < count && usable; ++i) {
                const glm::dvec3 n = normalMatrix * glm::dvec3(glm::vec3((*normals)[i]));
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

        // Tangents are surface directions: the linear part of the transform
        // carries them (normals need the inverse transpose). w is the sign of
        // the bitangent, B = w (N x T) (glTF 2.0, 3.7.2.1); a mirroring
        // transform reverses N x T against the mirrored B, so w changes sign.
        if (const auto tangents = attributes.read("TANGENT", TANGENT_FORMATS, count, components)) {
            out.tangents.resize(count);
            bool usable = !singular;
            for (size_t i = 0; i < count && usable; ++i) {
                const glm::vec4 t = (*tangents)[i];
                const glm::dvec3 d = linear * glm::dvec3(glm::vec3(t));
                const double length = glm::length(d);
                usable = length > 1e-12 && std::isfinite(length);
                const float sign = (t.w < 0.0f) != flip ? -1.0f : 1.0f;
                out.tangents[i] = glm::vec4(glm::vec3(d / length), sign);
            }
            if (!usable) {
                warnings.addCounted("zero-length tangents are dropped", "mesh", out.name);
                out.tangents.clear();
            }
        }

        // ---- texture coordinates and colours: as stored ----------------------
        // glTF's UV origin is the image's top-left corner, v running down
        // (glTF 2.0, 3.7.2.1 and 3.8.4); kept so, and textures are sampled
        // with that convention.
        for (const auto& [name, uv] :
             {std::pair{"TEXCOORD_0", &out.texcoords0}, std::pair{"TEXCOORD_1", &out.texcoords1}})
            if (const auto values = attributes.read(name, TEXCOORD_FORMATS, count, components))
                for (const glm::vec4& v : *values) uv->push_back(glm::vec2(v));

        if (const auto colors = attributes.read("COLOR_0", COLOR_FORMATS, count, components)) {
            // Linear RGB(A) multipliers of the base colour; RGB alone is opaque.
            bool clamped = false;
            for (const glm::vec4& c : *colors) {
                glm::vec4 color = components == 3 ? glm::vec4(glm::vec3(c), 1.0f) : c;
                const glm::vec4 inRange = glm::clamp(color, 0.0f, 1.0f);
                clamped |= inRange != color;
                out.colors.push_back(inRange);
            }
            if (clamped)
                warnings.addCounted("vertex colours outside [0, 1] are clamped", "mesh", out.name);
        }

        // ---- triangles -------------------------------------------------------
        std::vector<uint32_t> indices;
        if (primitive.indices >= 0) {
            indices = accessors.indices(primitive.indices, what + " indices");
        } else {
            indices.resize(count);
            for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
        }
        if (primitive.mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
            fail(file, "{}: {} {} is not a multiple of 3", what,
                 primitive.indices >= 0 ? "index count" : "vertex count", indices.size());
        // Strips and fans become lists of vertex indices, so every per-vertex
        // attribute comes along unchanged.
        indices = triangleList(primitive.mode, std::move(indices));
        size_t degenerate = 0;
        for (size_t t = 0; t < indices.size(); t += 3) {
            glm::uvec3 tri(indices[t], indices[t + 1], indices[t + 2]);
            for (int k = 0; k < 3; ++k)
                if (tri[k] >= count)
                    fail(file, "{}: index {} is out of range ({} vertices)", what, tri[k], count);
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
