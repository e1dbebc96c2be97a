#include "scene/tangents.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "shared/sampling.h"

namespace vkpath::scene {
namespace {

// What makes two corners one MikkTSpace vertex: position, normal and texture
// coordinates, equal by value (-0 is stored as +0, so equal values hash
// alike; a NaN equals nothing and stays a vertex of its own).
struct VertexKey {
    std::array<float, 8> values;

    bool operator==(const VertexKey& other) const {
        for (size_t i = 0; i < values.size(); ++i)
            if (!(values[i] == other.values[i])) return false;
        return true;
    }
};

struct VertexKeyHash {
    size_t operator()(const VertexKey& key) const {
        uint64_t h = 14695981039346656037ull;  // FNV-1a over the values' bits
        for (float v : key.values) {
            uint32_t bits;
            std::memcpy(&bits, &v, sizeof bits);
            h = (h ^ bits) * 1099511628211ull;
        }
        return size_t(h);
    }
};

VertexKey vertexKey(glm::vec3 p, glm::vec3 n, glm::vec2 uv) {
    return {{p.x + 0.0f, p.y + 0.0f, p.z + 0.0f, n.x + 0.0f, n.y + 0.0f, n.z + 0.0f, uv.x + 0.0f,
             uv.y + 0.0f}};
}

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// `v` made orthogonal to unit `n` and normalised; zero where nothing is left.
glm::dvec3 tangentPart(const glm::dvec3& v, const glm::dvec3& n) {
    const glm::dvec3 t = v - glm::dot(n, v) * n;
    const double length = glm::length(t);
    return length > 0.0 && std::isfinite(length) ? t / length : glm::dvec3(0.0);
}

// A unit vector orthogonal to `n`, for a vertex no triangle gives a tangent.
glm::vec3 anyTangent(const glm::dvec3& n) {
    const double length = glm::length(n);
    if (!(length > 0.0) || !std::isfinite(length)) return glm::vec3(1.0f, 0.0f, 0.0f);
    return shared::makeFrame(glm::vec3(n / length)).s;
}

// The corners of one vertex (by VertexKey) and orientation.
struct Group {
    glm::dvec3 normal;    // unit, or zero when the corners have none
    glm::dvec3 sum{0.0};  // of the corners' tangents, weighted by their angles
    float sign = 1.0f;    // the orientation: w
};

struct Triangle {
    bool valid = false;      // its indices are in range
    bool degenerate = true;  // no tangent: positions in a line or a UV area of 0
    float sign = 1.0f;
    glm::dvec3 tangent{0.0};     // dP/ds
    glm::dvec3 faceNormal{0.0};  // unit
};

class Generator {
  public:
    Generator(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
              std::span<const glm::vec2> uvs, std::span<const glm::uvec3> triangles)
        : m_positions(positions), m_normals(normals), m_uvs(uvs), m_triangles(triangles) {}

    MeshTangents run() {
        std::vector<Triangle> triangles(m_triangles.size());
        for (size_t i = 0; i < m_triangles.size(); ++i) triangles[i] = triangle(m_triangles[i]);
        // Corner groups: those of usable triangles first, so that the corners
        // of degenerate ones can join the groups their vertices already have.
        std::vector<int64_t> cornerGroup(m_triangles.size() * 3, -1);
        m_firstGroup.assign(m_positions.size(), -1);
        for (size_t i = 0; i < m_triangles.size(); ++i) {
            if (!triangles[i].valid || triangles[i].degenerate) continue;
            for (int k = 0; k < 3; ++k)
                cornerGroup[3 * i + k] = addCorner(triangles[i], m_triangles[i], k);
        }
        for (size_t i = 0; i < m_triangles.size(); ++i) {
            if (!triangles[i].valid || !triangles[i].degenerate) continue;
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = m_triangles[i][k];
                cornerGroup[3 * i + k] = m_firstGroup[v] >= 0
                                             ? m_firstGroup[v]
                                             : group(v, cornerNormal(triangles[i], v), 1.0f);
            }
        }
        return assemble(cornerGroup);
    }

  private:
    bool inRange(uint32_t v) const {
        return v < m_positions.size() && v < m_uvs.size() &&
               (m_normals.empty() || v < m_normals.size());
    }

    Triangle triangle(const glm::uvec3& indices) const {
        Triangle t;
        t.valid = inRange(indices.x) && inRange(indices.y) && inRange(indices.z);
        if (!t.valid) return t;
        const glm::dvec3 p0(m_positions[indices.x]), p1(m_positions[indices.y]),
            p2(m_positions[indices.z]);
        const glm::dvec3 d1 = p1 - p0, d2 = p2 - p0;
        // Texture coordinates with v up, MikkTSpace's convention (see the header).
        const glm::dvec2 uv0(m_uvs[indices.x]), uv1(m_uvs[indices.y]), uv2(m_uvs[indices.z]);
        const double s1 = uv1.x - uv0.x, t1 = -(uv1.y - uv0.y);
        const double s2 = uv2.x - uv0.x, t2 = -(uv2.y - uv0.y);
        const glm::dvec3 face = glm::cross(d1, d2);
        const double faceLength = glm::length(face);
        if (faceLength > 0.0 && std::isfinite(faceLength)) t.faceNormal = face / faceLength;
        // P(s, t) linear over the triangle: d1 = s1 dP/ds + t1 dP/dt and
        // d2 = s2 dP/ds + t2 dP/dt, solved for dP/ds (Mikkelsen 2008, eq. 4.2).
        const double area = s1 * t2 - s2 * t1;  // twice the signed UV area
        const glm::dvec3 tangent = (t2 * d1 - t1 * d2) / area;
        t.degenerate = !(faceLength > 0.0) || !std::isfinite(faceLength) || !(area != 0.0) ||
                       !finite(tangent) || !(glm::length(tangent) > 0.0);
        if (t.degenerate) return t;
        t.sign = area > 0.0 ? 1.0f : -1.0f;
        t.tangent = tangent;
        return t;
    }

    // The normal of vertex `v` in triangle `t`: its own, or the face's.
    glm::vec3 cornerNormal(const Triangle& t, uint32_t v) const {
        return m_normals.empty() ? glm::vec3(t.faceNormal) : m_normals[v];
    }

    // The group of vertex `v` (with normal `normal`) and orientation `sign`.
    int64_t group(uint32_t v, glm::vec3 normal, float sign) {
        const auto [weld, added] = m_welds.try_emplace(vertexKey(m_positions[v], normal, m_uvs[v]),
                                                       uint64_t(m_welds.size()));
        const uint64_t key = weld->second * 2 + (sign < 0.0f ? 1 : 0);
        const auto [it, created] = m_groupOf.try_emplace(key, int64_t(m_groups.size()));
        if (created) {
            Group g;
            const glm::dvec3 n(normal);
            const double length = glm::length(n);
            g.normal = length > 0.0 && std::isfinite(length) ? n / length : glm::dvec3(0.0);
            g.sign = sign;
            m_groups.push_back(g);
        }
        if (m_firstGroup[v] < 0) m_firstGroup[v] = it->second;
        return it->second;
    }

    // Adds corner k of usable triangle t (indices `indices`) to its group.
    int64_t addCorner(const Triangle& t, const glm::uvec3& indices, int k) {
        const uint32_t v = indices[k];
        const int64_t g = group(v, cornerNormal(t, v), t.sign);
        const glm::dvec3 n = m_groups[size_t(g)].normal;
        const glm::dvec3 tangent = tangentPart(t.tangent, n);
        // The corner's angle, between its edges as seen along the normal.
        const glm::dvec3 p(m_positions[v]);
        const glm::dvec3 a = tangentPart(glm::dvec3(m_positions[indices[(k + 1) % 3]]) - p, n);
        const glm::dvec3 b = tangentPart(glm::dvec3(m_positions[indices[(k + 2) % 3]]) - p, n);
        const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
        m_groups[size_t(g)].sum += angle * tangent;
        return g;
    }

    MeshTangents assemble(const std::vector<int64_t>& cornerGroup) const {
        MeshTangents out;
        const size_t n = m_positions.size();
        out.sourceVertex.resize(n);
        out.tangents.resize(n);
        for (uint32_t v = 0; v < n; ++v) {
            out.sourceVertex[v] = v;
            const glm::dvec3 normal =
                v < m_normals.size() ? glm::dvec3(m_normals[v]) : glm::dvec3(0.0);
            out.tangents[v] = glm::vec4(anyTangent(normal), 1.0f);  // used by no triangle
        }
        std::vector<glm::vec4> groupTangent(m_groups.size());
        for (size_t g = 0; g < m_groups.size(); ++g) {
            const glm::dvec3 t = tangentPart(m_groups[g].sum, m_groups[g].normal);
            const glm::vec3 unit =
                t != glm::dvec3(0.0) ? glm::vec3(t) : anyTangent(m_groups[g].normal);
            groupTangent[g] = glm::vec4(unit, m_groups[g].sign);
        }
        std::unordered_map<uint64_t, uint32_t>
            split;  // (input vertex, group) -> vertex, beyond the first group
        out.triangles.resize(m_triangles.size());
        for (size_t i = 0; i < m_triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = m_triangles[i][k];
                const int64_t g = cornerGroup[3 * i + k];
                uint32_t index = v;
                if (g >= 0 && g != m_firstGroup[v]) {
                    const auto [it, added] = split.try_emplace(uint64_t(v) << 32 | uint64_t(g),
                                                               uint32_t(out.sourceVertex.size()));
                    if (added) {
                        out.sourceVertex.push_back(v);
                        out.tangents.push_back(groupTangent[size_t(g)]);
                    }
                    index = it->second;
                } else if (g >= 0) {
                    out.tangents[v] = groupTangent[size_t(g)];
                }
                out.triangles[i][k] = index;
            }
        return out;
    }

    std::span<const glm::vec3> m_positions;
    std::span<const glm::vec3> m_normals;
    std::span<const glm::vec2> m_uvs;
    std::span<const glm::uvec3> m_triangles;
    std::unordered_map<VertexKey, uint64_t, VertexKeyHash> m_welds;  // vertex -> weld id
    std::unordered_map<uint64_t, int64_t> m_groupOf;  // weld id x 2 + (w < 0) -> group
    std::vector<Group> m_groups;
    std::vector<int64_t> m_firstGroup;  // per input vertex: the group that keeps its index
};

}  // namespace

MeshTangents generateTangents(std::span<const glm::vec3> positions,
                              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
                              std::span<const glm::uvec3> triangles) {
    return Generator(positions, normals, uvs, triangles).run();
}

}  // namespace vkpath::scene
