#include "scene/collada_geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace vkpath::scene::collada {
namespace {

// A cap so a broken or hostile file fails with a message instead of
// exhausting memory through instancing.
constexpr uint64_t MAX_TRIANGLES = 20'000'000;

// What makes corners one vertex: their position and normal (by index) and
// their texture coordinate's value (by bits): exporters such as Blender's
// give every corner a coordinate of its own, most of them equal.
struct VertexKey {
    uint32_t position, normal, u, v;
    bool operator==(const VertexKey&) const = default;
};

struct VertexKeyHash {
    size_t operator()(const VertexKey& k) const {
        const uint64_t a = uint64_t(k.position) << 32 | k.normal, b = uint64_t(k.u) << 32 | k.v;
        return std::hash<uint64_t>()(a * 0x9E3779B97F4A7C15ull ^ b);
    }
};

uint32_t bits(float value) {
    uint32_t b;
    std::memcpy(&b, &value, sizeof(b));
    return b;
}

}  // namespace

// The elements of a <source>, `width` (2: s t, or 3: x y z) numbers each,
// through its accessor; a third component of 2-wide elements is 0.
std::vector<glm::vec3> Geometry::readSource(pugi::xml_node source, size_t width,
                                            bool requireFinite) const {
    const std::string what = fmt::format("source '{}'", nameOf(source));
    const pugi::xml_node array = source.child("float_array");
    if (!array) fail(fmt::format("{} has no <float_array>", what));
    const std::vector<double> data = m_document.numbers(array, what);
    if (const pugi::xml_attribute count = array.attribute("count")) {
        const unsigned long long declared = count.as_ullong();
        if (declared > data.size())
            fail(fmt::format("{}: <float_array> has {} numbers, its count says {}", what,
                             data.size(), declared));
    }
    uint64_t count = data.size() / width, stride = width, offset = 0;
    if (const pugi::xml_node accessor = source.child("technique_common").child("accessor")) {
        count = accessor.attribute("count").as_ullong();
        stride = accessor.attribute("stride").as_ullong(1);
        offset = accessor.attribute("offset").as_ullong(0);
    }
    if (stride < width)
        fail(fmt::format("{}: accessor stride {} is below {} ({})", what, stride, width,
                         width == 3 ? "x y z" : "s t"));
    // Checked before multiplying so absurd counts cannot overflow.
    if (count > data.size() || stride > data.size() || offset > data.size() ||
        (count > 0 && offset + (count - 1) * stride + width > data.size()))
        fail(fmt::format("{}: accessor (count {}, stride {}, offset {}) reads past its {} numbers",
                         what, count, stride, offset, data.size()));
    std::vector<glm::vec3> out(count);
    for (uint64_t i = 0; i < count; ++i) {
        const double* v = &data[offset + i * stride];
        out[i] = glm::vec3(v[0], v[1], width == 3 ? v[2] : 0.0);
        if (requireFinite && !allFinite(out[i]))
            fail(fmt::format("{}: element {} {} is not finite", what, i, vecString(out[i])));
    }
    return out;
}

// One primitive element of a <mesh>: its inputs, index stride and polygons,
// triangulated as fans (polylist, polygons, trifans) or strips (tristrips).
void Geometry::readPrimitive(pugi::xml_node element, pugi::xml_node mesh,
                             const std::string& geometryName, LocalMesh& local) {
    const std::string_view kind = element.name();
    const std::string what = fmt::format("geometry '{}': <{}>", geometryName, kind);
    Primitive primitive;
    primitive.symbol = element.attribute("material").as_string();

    uint64_t stride = 1;
    std::optional<uint64_t> vertexOffset, normalOffset;
    bool normalsPerPosition = false;
    std::vector<glm::vec3> normals, texCoords;
    std::optional<uint64_t> texCoordOffset;
    unsigned texCoordSet = 0;
    for (pugi::xml_node input : element.children("input")) {
        const std::string_view semantic = input.attribute("semantic").as_string();
        const uint64_t offset = input.attribute("offset").as_ullong(0);
        if (offset > 1'000'000) fail(fmt::format("{}: input offset {} is absurd", what, offset));
        stride = std::max(stride, offset + 1);
        const char* sourceUrl = input.attribute("source").as_string(nullptr);
        if (semantic == "VERTEX") {
            const pugi::xml_node vertices = m_document.resolve(sourceUrl, "vertices", what);
            if (vertices.parent() != mesh)
                fail(fmt::format("{}: VERTEX refers to the <vertices> of another mesh", what));
            vertexOffset = offset;
            bool havePositions = false;
            for (pugi::xml_node vin : vertices.children("input")) {
                const std::string_view vsemantic = vin.attribute("semantic").as_string();
                const char* url = vin.attribute("source").as_string(nullptr);
                if (vsemantic == "POSITION") {
                    local.positions = readSource(m_document.resolve(url, "source", what), 3, true);
                    havePositions = true;
                } else if (vsemantic == "NORMAL") {
                    normals = readSource(m_document.resolve(url, "source", what), 3, false);
                    normalsPerPosition = true;
                }
            }
            if (!havePositions) fail(fmt::format("{}: its <vertices> has no POSITION input", what));
        } else if (semantic == "NORMAL") {
            normals = readSource(m_document.resolve(sourceUrl, "source", what), 3, false);
            normalOffset = offset;
            normalsPerPosition = false;
        } else if (semantic == "TEXCOORD" &&
                   (!texCoordOffset || input.attribute("set").as_uint(0) < texCoordSet)) {
            // The lowest set is Mesh::texcoords0 (Blender and Maya export one, set 0).
            texCoordSet = input.attribute("set").as_uint(0);
            texCoords = readSource(m_document.resolve(sourceUrl, "source", what), 2, true);
            texCoordOffset = offset;
        }
        // COLOR, further TEXCOORD sets, ...: not read.
    }
    if (!vertexOffset) fail(fmt::format("{} has no VERTEX input", what));
    if (normalsPerPosition && normals.size() < local.positions.size())
        fail(fmt::format("{}: {} per-vertex normals for {} positions", what, normals.size(),
                         local.positions.size()));

    // Every primitive of a mesh shares the <vertices>; normals are per
    // primitive, so they are appended and indices rebased.
    const uint32_t normalBase = static_cast<uint32_t>(local.normals.size());
    local.normals.insert(local.normals.end(), normals.begin(), normals.end());
    // COLLADA's t runs up from the image's bottom row (COLLADA 1.4.1, 6-8,
    // <input> TEXCOORD, as OpenGL); the scene model takes glTF's top-left
    // origin, so v = 1 - t.
    const uint32_t texCoordBase = static_cast<uint32_t>(local.texCoords.size());
    for (const glm::vec3& st : texCoords) local.texCoords.push_back({st.x, 1.0f - st.y});

    auto corner = [&](const std::vector<uint32_t>& p, uint64_t k) {
        const uint32_t position = p[k * stride + *vertexOffset];
        if (position >= local.positions.size())
            fail(fmt::format("{}: position index {} out of range of its source ({} elements)", what,
                             position, local.positions.size()));
        uint32_t normal = NO_INDEX, texCoord = NO_INDEX;
        if (normalOffset) {
            normal = p[k * stride + *normalOffset];
            if (normal >= normals.size())
                fail(fmt::format("{}: normal index {} out of range of its source ({} elements)",
                                 what, normal, normals.size()));
            normal += normalBase;
        } else if (normalsPerPosition) {
            normal = position + normalBase;
        }
        if (texCoordOffset) {
            texCoord = p[k * stride + *texCoordOffset];
            if (texCoord >= texCoords.size())
                fail(fmt::format("{}: TEXCOORD index {} out of range of its source ({} elements)",
                                 what, texCoord, texCoords.size()));
            texCoord += texCoordBase;
        }
        return Corner{position, normal, texCoord};
    };
    auto addFan = [&](const std::vector<uint32_t>& p, uint64_t first, uint64_t n) {
        if (n < 3) {
            ++local.degeneratePolygons;
            return;
        }
        for (uint64_t i = 1; i + 1 < n; ++i)
            for (uint64_t k : {first, first + i, first + i + 1})
                primitive.corners.push_back(corner(p, k));
    };
    auto addStrip = [&](const std::vector<uint32_t>& p, uint64_t n) {
        if (n < 3) {
            ++local.degeneratePolygons;
            return;
        }
        for (uint64_t i = 0; i + 2 < n; ++i) {
            // Every other triangle of a strip is listed clockwise.
            const bool odd = i % 2 == 1;
            for (uint64_t k : {i, odd ? i + 2 : i + 1, odd ? i + 1 : i + 2})
                primitive.corners.push_back(corner(p, k));
        }
    };
    auto checkedIndices = [&](pugi::xml_node p, uint64_t cornersNeeded) {
        std::vector<uint32_t> values = m_document.indices(p, what + " <p>");
        if (cornersNeeded > values.size() / stride)
            fail(fmt::format("{}: <p> has {} indices, needs {} ({} corners of {} inputs)", what,
                             values.size(), cornersNeeded * stride, cornersNeeded, stride));
        return values;
    };

    const pugi::xml_attribute countAttribute = element.attribute("count");
    uint64_t count = countAttribute.as_ullong(0);
    if (kind == "polylist") {
        const std::vector<uint32_t> vcount =
            m_document.indices(element.child("vcount"), what + " <vcount>");
        if (!countAttribute) count = vcount.size();
        if (count > vcount.size())
            fail(fmt::format("{}: <vcount> has {} entries, count says {}", what, vcount.size(),
                             count));
        uint64_t total = 0;
        for (uint64_t i = 0; i < count; ++i) total += vcount[i];  // each < 2^32: no overflow
        const std::vector<uint32_t> p = checkedIndices(element.child("p"), total);
        uint64_t first = 0;
        for (uint64_t i = 0; i < count; ++i) {
            addFan(p, first, vcount[i]);
            first += vcount[i];
        }
    } else if (kind == "triangles") {
        if (!countAttribute)
            count = m_document.indices(element.child("p"), what + " <p>").size() / stride / 3;
        const std::vector<uint32_t> p = checkedIndices(element.child("p"), count * 3);
        for (uint64_t t = 0; t < count; ++t) addFan(p, t * 3, 3);
    } else {
        // <polygons>, <trifans>, <tristrips>: one <p> per polygon, fan or strip.
        uint64_t seen = 0;
        for (pugi::xml_node pNode : element.children("p")) {
            const std::vector<uint32_t> p = checkedIndices(pNode, 0);
            const uint64_t n = p.size() / stride;
            if (kind == "tristrips")
                addStrip(p, n);
            else
                addFan(p, 0, n);
            ++seen;
        }
        if (element.child("ph"))
            m_warnings.addExample(
                "holes",
                fmt::format("{}: polygons with holes (<ph>) are not supported; ignored", what));
        if (seen < count)
            fail(fmt::format("{}: has {} <p> elements, count says {}", what, seen, count));
    }
    local.primitives.push_back(std::move(primitive));
}

const LocalMesh& Geometry::localMesh(pugi::xml_node geometry) {
    const auto cached = m_localMeshes.find(geometry.internal_object());
    if (cached != m_localMeshes.end()) return cached->second;
    const std::string geometryName = nameOf(geometry);
    const pugi::xml_node mesh = geometry.child("mesh");
    LocalMesh local;
    for (pugi::xml_node element : mesh.children()) {
        const std::string_view kind = element.name();
        if (kind == "polylist" || kind == "triangles" || kind == "polygons" || kind == "trifans" ||
            kind == "tristrips") {
            readPrimitive(element, mesh, geometryName, local);
        } else if (kind == "lines" || kind == "linestrips") {
            m_warnings.addExample("lines", fmt::format("geometry '{}': <{}> has no area; ignored",
                                                       geometryName, kind));
        }
    }
    return m_localMeshes.emplace(geometry.internal_object(), std::move(local)).first->second;
}

void Geometry::addMeshInstance(const LocalMesh& local, const glm::dmat4& world,
                               const std::string& nodeName,
                               const std::function<uint32_t(const std::string&)>& materialFor,
                               std::vector<Mesh>& meshes) {
    m_droppedTriangles += local.degeneratePolygons;
    const glm::dmat3 linear(world);
    const double det = glm::determinant(linear);
    // Cofactor matrix = det * inverse transpose: transforms normals (and maps
    // a x b to (La) x (Lb)) even when the transform is singular.
    const glm::dmat3 cofactor(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                              glm::cross(linear[0], linear[1]));
    const bool flip = det < 0;

    std::vector<glm::vec3> positions(local.positions.size());
    for (size_t i = 0; i < positions.size(); ++i)
        positions[i] = glm::vec3(world * glm::dvec4(glm::dvec3(local.positions[i]), 1.0));
    std::vector<glm::vec3> normals(local.normals.size());
    std::vector<uint8_t> normalValid(local.normals.size(), 0);
    for (size_t i = 0; i < normals.size(); ++i) {
        glm::dvec3 n = cofactor * glm::dvec3(local.normals[i]);
        if (flip) n = -n;
        const double len = glm::length(n);
        if (len > 0 && std::isfinite(len)) {
            normals[i] = glm::vec3(n / len);
            normalValid[i] = allFinite(normals[i]);
        }
    }

    for (size_t k = 0; k < local.primitives.size(); ++k) {
        const Primitive& primitive = local.primitives[k];
        const size_t triangleCount = primitive.corners.size() / 3;

        // Pass 1: which triangles survive, their face normals, and whether
        // the corner normals say anything the faces do not.
        std::vector<glm::vec3> faceNormals(triangleCount);
        std::vector<uint8_t> keep(triangleCount, 0);
        bool anyNormals = false, flat = true;
        auto cornerOf = [&](size_t t, int i) {
            // A mirroring transform turns counter-clockwise into clockwise.
            const int j = flip && i > 0 ? 3 - i : i;
            return primitive.corners[t * 3 + j];
        };
        for (size_t t = 0; t < triangleCount; ++t) {
            const glm::vec3 p0 = positions[cornerOf(t, 0).position];
            const glm::vec3 p1 = positions[cornerOf(t, 1).position];
            const glm::vec3 p2 = positions[cornerOf(t, 2).position];
            const glm::vec3 e1 = p1 - p0, e2 = p2 - p0, e3 = p2 - p1;
            const glm::vec3 cross = glm::cross(e1, e2);
            const float twiceArea = glm::length(cross);
            const float longest = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
            // Relative test: the sine of the smallest angle below float
            // precision means no well-defined plane.
            if (!allFinite(p0) || !allFinite(p1) || !allFinite(p2) || !std::isfinite(twiceArea) ||
                !(twiceArea > 1e-7f * longest)) {
                ++m_droppedTriangles;
                continue;
            }
            keep[t] = 1;
            faceNormals[t] = cross / twiceArea;
            for (int i = 0; i < 3; ++i) {
                const uint32_t n = cornerOf(t, i).normal;
                if (n == NO_INDEX) continue;
                anyNormals = true;
                if (!normalValid[n]) {
                    ++m_replacedNormals;
                    continue;
                }
                flat = flat && glm::dot(normals[n], faceNormals[t]) > 1.0f - 1e-4f;
            }
        }
        const bool keepNormals = anyNormals && !flat;

        // Pass 2: vertices shared per VertexKey.
        Mesh mesh;
        mesh.name = local.primitives.size() > 1 ? fmt::format("{}#{}", nodeName, k) : nodeName;
        mesh.material = materialFor(primitive.symbol);
        const bool texCoords =
            !primitive.corners.empty() && primitive.corners[0].texCoord != NO_INDEX;
        std::unordered_map<VertexKey, uint32_t, VertexKeyHash> vertexOf;
        auto addVertex = [&](const Corner& c, const glm::vec3& normal) {
            mesh.positions.push_back(positions[c.position]);
            if (keepNormals) mesh.normals.push_back(normal);
            if (texCoords) mesh.texcoords0.push_back(local.texCoords[c.texCoord]);
            return static_cast<uint32_t>(mesh.positions.size() - 1);
        };
        auto vertex = [&](const Corner& c, const glm::vec3& faceNormal) -> uint32_t {
            const bool ownNormal = keepNormals && c.normal != NO_INDEX && normalValid[c.normal];
            // An invalid normal: this corner takes its face's, unshared.
            if (keepNormals && !ownNormal) return addVertex(c, faceNormal);
            const glm::vec2 uv = texCoords ? local.texCoords[c.texCoord] : glm::vec2(0.0f);
            const VertexKey key{c.position, ownNormal ? c.normal : NO_INDEX, bits(uv.x),
                                bits(uv.y)};
            const auto found = vertexOf.find(key);
            if (found != vertexOf.end()) return found->second;
            const uint32_t index = addVertex(c, ownNormal ? normals[c.normal] : glm::vec3(0.0f));
            vertexOf.emplace(key, index);
            return index;
        };
        for (size_t t = 0; t < triangleCount; ++t) {
            if (!keep[t]) continue;
            glm::uvec3 tri;
            for (int i = 0; i < 3; ++i) tri[i] = vertex(cornerOf(t, i), faceNormals[t]);
            mesh.triangles.push_back(tri);
        }
        if (mesh.triangles.empty()) continue;
        m_triangles += mesh.triangles.size();
        if (m_triangles > MAX_TRIANGLES)
            fail(fmt::format("more than {} triangles after instancing", MAX_TRIANGLES));
        meshes.push_back(std::move(mesh));
    }
}

std::optional<Sphere> Geometry::sphereInstance(double radius, const glm::dmat4& world,
                                               const std::string& nodeName) {
    const glm::dmat3 linear(world);
    const double s0 = glm::length(linear[0]), s1 = glm::length(linear[1]),
                 s2 = glm::length(linear[2]);
    const double largest = std::max({s0, s1, s2}), smallest = std::min({s0, s1, s2});
    const glm::vec3 center(world * glm::dvec4(0, 0, 0, 1));
    if (!(largest > 0) || !allFinite(center)) {
        m_warnings.addExample(
            "sphere-degenerate",
            fmt::format("node '{}': sphere with a zero-scale transform dropped", nodeName));
        return std::nullopt;
    }
    // Uniform scale: equal, mutually orthogonal columns.
    const double tolerance = 1e-4 * largest * largest;
    const bool orthogonal = std::abs(glm::dot(linear[0], linear[1])) < tolerance &&
                            std::abs(glm::dot(linear[1], linear[2])) < tolerance &&
                            std::abs(glm::dot(linear[0], linear[2])) < tolerance;
    double scale = largest;
    if (!orthogonal || largest - smallest > 1e-4 * largest) {
        scale = (s0 + s1 + s2) / 3.0;
        m_warnings.addExample("sphere-scale",
                              fmt::format("node '{}': non-uniform scale ({:g}, {:g}, {:g}) on a "
                                          "sphere; approximated by a sphere of the mean scale {:g}",
                                          nodeName, s0, s1, s2, scale));
    }
    Sphere sphere;
    sphere.name = nodeName;
    sphere.center = center;
    sphere.radius = static_cast<float>(radius * scale);
    if (!(sphere.radius > 0) || !std::isfinite(sphere.radius))
        fail(fmt::format("node '{}': sphere radius {} is not a positive float", nodeName,
                         radius * scale));
    return sphere;
}

}  // namespace vkpath::scene::collada
