// The MikkTSpace-compatible tangent generator (host/scene/tangents) on meshes
// whose tangent frames are known in closed form: a plane, the plane with its
// texture turned or mirrored, a cylinder whose facets' tangents project to
// the circle's exact tangent at every vertex, a mirror seam that splits its
// vertices, flat shading without normals, and degenerate input that must
// still give unit tangents, never NaN.
#include "scene/tangents.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace {

using namespace vkpath;

constexpr double PI = 3.14159265358979323846;

struct Grid {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
    std::vector<glm::uvec3> triangles;

    scene::MeshTangents tangents() const {
        return scene::generateTangents(positions, normals, uvs, triangles);
    }
};

// The square [-1, 1]^2 in y = 0, facing +y, as a (cells + 1)^2 vertex grid
// whose texture coordinates are uv(x, z); triangles counter-clockwise from
// above.
Grid plane(int cells, const std::function<glm::vec2(float, float)>& uv) {
    Grid g;
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) {
            const float x = -1.0f + 2.0f * float(i) / float(cells),
                        z = -1.0f + 2.0f * float(j) / float(cells);
            g.positions.emplace_back(x, 0.0f, z);
            g.normals.emplace_back(0.0f, 1.0f, 0.0f);
            g.uvs.push_back(uv(x, z));
        }
    const auto at = [&](int i, int j) { return uint32_t(j * (cells + 1) + i); };
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            g.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            g.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    return g;
}

void expectTangent(const glm::vec4& got, glm::dvec3 expected, float w, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], expected[c], 1e-6) << what << " component " << c;
    EXPECT_EQ(got.w, w) << what;
}

// u along +x, v along +z: the image lies upright seen from above with -z up
// the page, since glTF's v runs down the image. T = dP/du = +x, and the
// bitangent glTF rebuilds, w (N x T) = w (y x x) = -w z, must point up the
// image (decreasing v, -z): w = +1.
TEST(Tangents, PlaneFollowsTheTextureAxes) {
    const Grid g = plane(3, [](float x, float z) { return glm::vec2((x + 1) / 2, (z + 1) / 2); });
    const scene::MeshTangents t = g.tangents();
    ASSERT_EQ(t.tangents.size(), g.positions.size());  // nothing split
    EXPECT_EQ(t.triangles, g.triangles);
    for (size_t v = 0; v < t.tangents.size(); ++v) {
        EXPECT_EQ(t.sourceVertex[v], v);
        expectTangent(t.tangents[v], {1, 0, 0}, 1.0f, "vertex " + std::to_string(v));
        const glm::vec3 bitangent =
            t.tangents[v].w * glm::cross(g.normals[v], glm::vec3(t.tangents[v]));
        EXPECT_NEAR(bitangent.z, -1.0f, 1e-6f) << "the bitangent points up the image";
    }
}

// The texture turned by 90 degrees on the plane (u along -z, v along +x):
// T = dP/du = -z, and B = N x T = y x -z = -x points to decreasing v.
// Scaled coordinates (u over [0, 7]) change nothing: only directions count.
TEST(Tangents, TurnedAndScaledTexture) {
    const Grid g =
        plane(2, [](float x, float z) { return glm::vec2(7.0f * (1 - z) / 2, (x + 1) / 2); });
    const scene::MeshTangents t = g.tangents();
    ASSERT_EQ(t.tangents.size(), g.positions.size());
    for (size_t v = 0; v < t.tangents.size(); ++v)
        expectTangent(t.tangents[v], {0, 0, -1}, 1.0f, "turned");
}

// Mirrored in u (u along -x): the texture is seen from behind, T = -x and
// the frame is left-handed, w = -1, so that B = -(y x -x) = -z still points
// up the image.
TEST(Tangents, MirroredTextureGivesNegativeW) {
    const Grid g = plane(2, [](float x, float z) { return glm::vec2((1 - x) / 2, (z + 1) / 2); });
    const scene::MeshTangents t = g.tangents();
    ASSERT_EQ(t.tangents.size(), g.positions.size());
    for (size_t v = 0; v < t.tangents.size(); ++v) {
        expectTangent(t.tangents[v], {-1, 0, 0}, -1.0f, "mirrored");
        const glm::vec3 bitangent =
            t.tangents[v].w * glm::cross(g.normals[v], glm::vec3(t.tangents[v]));
        EXPECT_NEAR(bitangent.z, -1.0f, 1e-6f);
    }
}

// A texture mirrored about x = 0 (u = |x|), as modellers lay out symmetric
// models: the vertices on the seam are one vertex to MikkTSpace (same
// position, normal and uv) with corners of both orientations, so each is
// split in two, one per side; the right side keeps T = +x, w = +1, the left
// T = -x, w = -1.
TEST(Tangents, MirrorSeamSplitsItsVertices) {
    const Grid g = plane(4, [](float x, float z) { return glm::vec2(std::abs(x), (z + 1) / 2); });
    const scene::MeshTangents t = g.tangents();
    ASSERT_EQ(t.tangents.size(), g.positions.size() + 5);  // the five vertices at x = 0
    ASSERT_EQ(t.sourceVertex.size(), t.tangents.size());
    for (size_t v = g.positions.size(); v < t.sourceVertex.size(); ++v)
        EXPECT_EQ(g.positions[t.sourceVertex[v]].x, 0.0f);
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        const glm::vec3 centre = (g.positions[g.triangles[i].x] + g.positions[g.triangles[i].y] +
                                  g.positions[g.triangles[i].z]) /
                                 3.0f;
        const bool right = centre.x > 0;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = t.triangles[i][k];
            EXPECT_EQ(t.sourceVertex[v], g.triangles[i][k])
                << "the split vertex copies its input vertex";
            expectTangent(t.tangents[v], {right ? 1 : -1, 0, 0}, right ? 1.0f : -1.0f,
                          "triangle " + std::to_string(i) + " corner " + std::to_string(k));
        }
    }
}

// A cylinder of radius 1 about +y, u = phi / 2 pi around it, v down its
// height (v = 0 at the top). Each facet's dP/du is the chord between two
// vertices; projected into the plane of a vertex's radial normal it is the
// circle's tangent there, d/dphi (cos phi, 0, -sin phi) = (-sin phi, 0,
// -cos phi) for phi counted counter-clockwise seen from above, exactly,
// whatever the segment count. w = +1: B = N x T must be +y, up the image.
TEST(Tangents, CylinderHasTheCircleTangentAtEveryVertex) {
    constexpr int SEGMENTS = 12, ROWS = 3;
    Grid g;
    for (int j = 0; j <= ROWS; ++j)
        for (int i = 0; i <= SEGMENTS; ++i) {  // i = SEGMENTS repeats i = 0 with u = 1: the seam
            const double phi = 2 * PI * i / SEGMENTS;
            const glm::dvec3 radial(std::cos(phi), 0.0, -std::sin(phi));
            g.positions.emplace_back(glm::vec3(radial) +
                                     glm::vec3(0.0f, 1.0f - float(j) / ROWS, 0.0f));
            g.normals.emplace_back(radial);
            g.uvs.emplace_back(float(i) / SEGMENTS, float(j) / ROWS);
        }
    const auto at = [](int i, int j) { return uint32_t(j * (SEGMENTS + 1) + i); };
    for (int j = 0; j < ROWS; ++j)
        for (int i = 0; i < SEGMENTS; ++i) {  // counter-clockwise seen from outside
            g.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            g.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    for (const glm::uvec3& tri : g.triangles) {  // the winding faces out
        const glm::vec3 face = glm::cross(g.positions[tri.y] - g.positions[tri.x],
                                          g.positions[tri.z] - g.positions[tri.x]);
        ASSERT_GT(glm::dot(face, g.normals[tri.x]), 0.0f);
    }
    const scene::MeshTangents t = g.tangents();
    ASSERT_EQ(t.tangents.size(), g.positions.size());
    for (size_t v = 0; v < g.positions.size(); ++v) {
        const double phi = 2 * PI * (v % (SEGMENTS + 1)) / SEGMENTS;
        expectTangent(t.tangents[v], {-std::sin(phi), 0, -std::cos(phi)}, 1.0f,
                      "vertex " + std::to_string(v));
        const glm::vec3 bitangent =
            t.tangents[v].w * glm::cross(g.normals[v], glm::vec3(t.tangents[v]));
        EXPECT_NEAR(bitangent.y, 1.0f, 1e-6f);
    }
}

// Vertices equal in position, normal and uv are one MikkTSpace vertex even
// under different indices: two triangles that share the origin by value
// (vertices 0 and 3) get one tangent there, the angle-weighted mean of
// theirs (both corners are right angles: equal weights). The first has u
// along +x; the second u = x + z, v = z - x, so its dP/du is (x + z) / 2.
TEST(Tangents, VerticesEqualByValueShareATangent) {
    Grid g;
    g.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 0, 0}, {0, 0, -1}, {-1, 0, 0}};
    g.normals.assign(6, glm::vec3(0, 1, 0));
    g.uvs = {{0, 0}, {0, 1}, {1, 0}, {0, 0}, {-1, -1}, {-1, 1}};
    g.triangles = {{0, 1, 2}, {3, 4, 5}};
    const scene::MeshTangents t = g.tangents();
    ASSERT_EQ(t.tangents.size(), 6u);
    EXPECT_EQ(t.tangents[0], t.tangents[3]);
    for (int v : {1, 2}) expectTangent(t.tangents[v], {1, 0, 0}, 1.0f, "first triangle alone");
    for (int v : {4, 5})
        expectTangent(t.tangents[v], glm::normalize(glm::dvec3(1, 0, 1)), 1.0f, "second alone");
    expectTangent(t.tangents[0],
                  glm::normalize(glm::dvec3(1, 0, 0) + glm::normalize(glm::dvec3(1, 0, 1))), 1.0f,
                  "shared");
}

// Without normals (glTF: flat shading) each triangle's corners have its face
// normal: a vertex shared by faces of a cube is a different MikkTSpace vertex
// on each face, so it is split, and every corner's tangent lies in its face.
TEST(Tangents, FlatShadingWithoutNormalsSplitsPerFace) {
    Grid g;
    // Two faces of a unit cube sharing the edge x = 1, z = 1: the top (y = 1)
    // and the front (z = 1), one uv square each.
    g.positions = {{0, 1, 1}, {1, 1, 1}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}};
    g.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 1}, {1, 1}};
    g.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 1}, {4, 1, 0}};
    const scene::MeshTangents t = g.tangents();
    EXPECT_EQ(t.tangents.size(), 8u);  // vertices 0 and 1 belong to both faces
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        const glm::vec3 normal = i < 2 ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 tangent = t.tangents[t.triangles[i][k]];
            EXPECT_NEAR(glm::dot(glm::vec3(tangent), normal), 0.0f, 1e-6f);
            expectTangent(tangent, {1, 0, 0}, i < 2 ? -1.0f : 1.0f,
                          "face " + std::to_string(i / 2));
        }
    }
}

bool unitAndFinite(const glm::vec4& t) {
    return std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z) &&
           std::abs(glm::length(glm::vec3(t)) - 1.0f) < 1e-6f && (t.w == 1.0f || t.w == -1.0f);
}

// Degenerate texture coordinates give no tangent of their own: a triangle
// whose three uvs are equal takes its vertices' frames from their other
// triangles; a mesh whose uvs are all equal (or NaN), or whose triangle has
// its positions in a line, still gets unit tangents orthogonal to the
// normals, w = +-1, no NaN.
TEST(Tangents, DegenerateInputGivesUnitTangentsNeverNaN) {
    {
        // The unit plane and a triangle off its edge x = 1 that shares vertex
        // 1 (uv (1, 0)) and whose other two uvs are (1, 0) too.
        Grid g = plane(1, [](float x, float z) { return glm::vec2((x + 1) / 2, (z + 1) / 2); });
        g.positions.insert(g.positions.end(), {{2, 0, 0}, {2, 0, -1}});
        g.normals.insert(g.normals.end(), 2, glm::vec3(0, 1, 0));
        g.uvs.insert(g.uvs.end(), 2, glm::vec2(1, 0));
        g.triangles.push_back({1, 4, 5});
        const scene::MeshTangents t = g.tangents();
        ASSERT_EQ(t.tangents.size(), g.positions.size());
        for (const glm::vec4& tangent : t.tangents) EXPECT_TRUE(unitAndFinite(tangent));
        expectTangent(t.tangents[1], {1, 0, 0}, 1.0f, "the shared vertex keeps the plane's frame");
        EXPECT_EQ(t.triangles[2], glm::uvec3(1, 4, 5));
    }
    for (const glm::vec2 uv : {glm::vec2(0.5f, 0.5f), glm::vec2(NAN, 0.0f)}) {
        Grid g = plane(2, [&](float, float) { return uv; });
        const scene::MeshTangents t = g.tangents();
        ASSERT_EQ(t.tangents.size(), g.positions.size());
        for (const glm::vec4& tangent : t.tangents) {
            EXPECT_TRUE(unitAndFinite(tangent));
            EXPECT_NEAR(tangent.y, 0.0f, 1e-6f) << "orthogonal to the normal +y";
        }
    }
    {
        Grid g;
        g.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};  // in a line: no face normal either
        g.uvs = {{0, 0}, {1, 0}, {0, 1}};
        g.triangles = {{0, 1, 2},
                       {0, 1, 7}};  // the second has an index out of range: kept as it is
        const scene::MeshTangents t = g.tangents();
        ASSERT_EQ(t.tangents.size(), 3u);
        for (const glm::vec4& tangent : t.tangents) EXPECT_TRUE(unitAndFinite(tangent));
        EXPECT_EQ(t.triangles[1], glm::uvec3(0, 1, 7));
    }
}

}  // namespace
