// Scenes, rays and tracers shared by the BVH tests: generated geometry (triangle
// soups, sphere fields, closed meshes), brute-force closest hits on the CPU
// with the kernels' own intersection functions, and the test trace kernels
// dispatched through the harness. Every BVH built here passes integrityCheck.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/bvh_view.h"
#include "bvh/gpu_bvh.h"
#include "scene/scene.h"
#include "shared/bvh.h"
#include "shared/intersect.h"
#include "shared/ray.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"
#include "wavefront/kernel_features.h"

namespace vkpath::test::bvh {

using glm::vec3;
using shared::BvhPrimitive;
using shared::Hit;
using shared::Ray;

constexpr float FLT_MAX_VALUE = 3.402823466e+38f;

// ---- scenes ------------------------------------------------------------------

inline scene::Scene emptyScene() {
    scene::Scene s;
    s.materials.push_back(scene::Material{});
    s.materials.push_back(scene::Material{.name = "second"});
    return s;
}

inline vec3 randomInBox(std::mt19937& rng, vec3 lo, vec3 hi) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return lo + vec3(u(rng), u(rng), u(rng)) * (hi - lo);
}

inline vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    while (true) {
        const vec3 d(n(rng), n(rng), n(rng));
        const float len = glm::length(d);
        if (len > 1e-3f) return d / len;
    }
}

// `count` triangles with random vertices, each within `size` of a random
// centre in [-1, 1]^3; they intersect each other freely.
inline void addTriangleSoup(scene::Scene& s, uint32_t count, float size, uint32_t seed) {
    std::mt19937 rng(seed);
    scene::Mesh mesh;
    mesh.name = "soup";
    mesh.material = 1;
    for (uint32_t i = 0; i < count; ++i) {
        const vec3 c = randomInBox(rng, vec3(-1.0f), vec3(1.0f));
        const auto base = static_cast<uint32_t>(mesh.positions.size());
        for (int k = 0; k < 3; ++k)
            mesh.positions.push_back(c + randomInBox(rng, vec3(-size), vec3(size)));
        mesh.triangles.emplace_back(base, base + 1, base + 2);
    }
    s.meshes.push_back(std::move(mesh));
}

inline void addSphereField(scene::Scene& s, uint32_t count, float minRadius, float maxRadius,
                           uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> radius(minRadius, maxRadius);
    for (uint32_t i = 0; i < count; ++i)
        s.spheres.push_back(scene::Sphere{.name = "s",
                                          .center = randomInBox(rng, vec3(-1.0f), vec3(1.0f)),
                                          .radius = radius(rng),
                                          .material = i % 2});
}

// A closed icosphere: the icosahedron with each face split into 4^subdivisions
// triangles, vertices shared between faces (edge midpoints deduplicated), so
// neighbouring triangles use bit-identical vertices.
inline scene::Mesh icosphere(uint32_t subdivisions, float radius, vec3 center) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<vec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                              {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                              {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (vec3& v : unit) v = glm::normalize(v);
    std::vector<glm::uvec3> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                     {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                     {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                     {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (uint32_t s = 0; s < subdivisions; ++s) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto it = midpoints.find(key);
            if (it != midpoints.end()) return it->second;
            unit.push_back(glm::normalize(unit[a] + unit[b]));
            const auto index = static_cast<uint32_t>(unit.size() - 1);
            midpoints.emplace(key, index);
            return index;
        };
        std::vector<glm::uvec3> next;
        for (const glm::uvec3& f : faces) {
            const uint32_t a = midpoint(f.x, f.y), b = midpoint(f.y, f.z), c = midpoint(f.z, f.x);
            next.insert(next.end(), {{f.x, a, c}, {f.y, b, a}, {f.z, c, b}, {a, b, c}});
        }
        faces = std::move(next);
    }
    scene::Mesh mesh;
    mesh.name = "icosphere";
    for (const vec3& v : unit) mesh.positions.push_back(center + radius * v);
    mesh.triangles = std::move(faces);
    return mesh;
}

// The closed surface of the cube [-1, 1]^3, each face an n x n grid of quads
// split into two triangles; vertices on the cube's edges are shared by the
// faces that meet there.
inline scene::Mesh tessellatedCube(uint32_t n) {
    scene::Mesh mesh;
    mesh.name = "cube";
    std::map<std::tuple<float, float, float>, uint32_t> index;
    auto vertex = [&](vec3 p) {
        const auto key = std::make_tuple(p.x, p.y, p.z);
        const auto it = index.find(key);
        if (it != index.end()) return it->second;
        mesh.positions.push_back(p);
        const auto i = static_cast<uint32_t>(mesh.positions.size() - 1);
        index.emplace(key, i);
        return i;
    };
    auto coordinate = [n](uint32_t i) {
        return -1.0f + 2.0f * static_cast<float>(i) / static_cast<float>(n);
    };
    for (int axis = 0; axis < 3; ++axis) {
        for (float side : {-1.0f, 1.0f}) {
            for (uint32_t i = 0; i < n; ++i) {
                for (uint32_t j = 0; j < n; ++j) {
                    auto at = [&](uint32_t a, uint32_t b) {
                        vec3 p;
                        p[axis] = side;
                        p[(axis + 1) % 3] = coordinate(a);
                        p[(axis + 2) % 3] = coordinate(b);
                        return vertex(p);
                    };
                    const uint32_t v00 = at(i, j), v10 = at(i + 1, j), v01 = at(i, j + 1),
                                   v11 = at(i + 1, j + 1);
                    mesh.triangles.emplace_back(v00, v10, v11);
                    mesh.triangles.emplace_back(v00, v11, v01);
                }
            }
        }
    }
    return mesh;
}

// ---- building --------------------------------------------------------------

// Builds and runs the integrity check (every BVH the tests build is checked).
inline vkpath::bvh::BvhBuild buildChecked(const scene::Scene& s,
                                          const vkpath::bvh::BvhOptions& options = {}) {
    vkpath::bvh::BvhBuild build = vkpath::bvh::buildBvh(s, options);
    const std::vector<std::string> problems = vkpath::bvh::integrityCheck(build, s);
    for (const std::string& p : problems) ADD_FAILURE() << "BVH integrity: " << p;
    return build;
}

// ---- rays ----------------------------------------------------------------------

inline Ray makeRay(vec3 origin, vec3 direction, float tMax = FLT_MAX_VALUE, uint32_t pixel = 0) {
    Ray r;
    r.origin = origin;
    r.direction = direction;
    r.tMax = tMax;
    r.pixel = pixel;
    return r;
}

// A point inside primitive `p` (triangle: barycentrics at least `margin`;
// sphere: a point of its surface facing `from`... any surface point).
inline vec3 pointOn(const BvhPrimitive& p, std::mt19937& rng, float margin = 0.0f) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    if (p.kind == VKP_PRIMITIVE_SPHERE) return p.p0 + p.p1.x * randomDirection(rng);
    float b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1.0f) {
        b1 = 1.0f - b1;
        b2 = 1.0f - b2;
    }
    const float scale = 1.0f - 3.0f * margin;
    b1 = margin + scale * b1;
    b2 = margin + scale * b2;
    return (1.0f - b1 - b2) * p.p0 + b1 * p.p1 + b2 * p.p2;
}

// Half random rays from the box [lo, hi], half aimed from there at a random
// point of a random primitive (so most of them hit something).
inline std::vector<Ray> randomRays(const vkpath::bvh::BvhBuild& build, uint32_t count,
                                   uint32_t seed, vec3 lo = vec3(-2.0f), vec3 hi = vec3(2.0f)) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays(count);
    std::uniform_int_distribution<size_t> pick(0, build.primitives.size() - 1);
    for (uint32_t i = 0; i < count; ++i) {
        const vec3 origin = randomInBox(rng, lo, hi);
        vec3 direction = randomDirection(rng);
        if (i % 2 == 1) {
            const vec3 to = pointOn(build.primitives[pick(rng)], rng) - origin;
            if (glm::length(to) > 1e-4f) direction = glm::normalize(to);
        }
        rays[i] = makeRay(origin, direction, FLT_MAX_VALUE, i);
    }
    return rays;
}

struct AimedRays {
    std::vector<Ray> rays;
    std::vector<float> distance;  // to the aimed-at point
};

// Rays from inside [-0.5, 0.5]^3 (1% from the exact origin) to points on the
// mesh's edges (half) or exactly at its vertices (half).
inline AimedRays raysAtEdgesAndVertices(const scene::Mesh& mesh, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<size_t> pickTriangle(0, mesh.triangles.size() - 1);
    std::uniform_int_distribution<int> pickCorner(0, 2);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    AimedRays out;
    out.rays.reserve(count);
    out.distance.reserve(count);
    while (out.rays.size() < count) {
        const vec3 origin =
            out.rays.size() % 100 == 0 ? vec3(0.0f) : randomInBox(rng, vec3(-0.5f), vec3(0.5f));
        const glm::uvec3 tri = mesh.triangles[pickTriangle(rng)];
        const int corner = pickCorner(rng);
        const vec3 a = mesh.positions[tri[corner]];
        const vec3 b = mesh.positions[tri[(corner + 1) % 3]];
        const vec3 target = out.rays.size() % 2 == 0 ? a : a + u(rng) * (b - a);
        const vec3 to = target - origin;
        const float length = glm::length(to);
        out.rays.push_back(makeRay(origin, to / length));
        out.distance.push_back(length);
    }
    return out;
}

// ---- CPU brute force -----------------------------------------------------------

// The intersection of one primitive, with the traversal's functions.
inline bool intersectPrimitive(const BvhPrimitive& p, const Ray& ray, float tMax, float& t,
                               glm::vec2& bary) {
    bary = glm::vec2(0.0f);
    if (p.kind == VKP_PRIMITIVE_SPHERE)
        return shared::intersectSphere(ray.origin, ray.direction, p.p0, p.p1.x, tMax, t);
    return shared::intersectTriangle(shared::makeTriangleRay(ray.origin, ray.direction), p.p0, p.p1,
                                     p.p2, tMax, t, bary);
}

inline Hit bruteForceClosest(const std::vector<BvhPrimitive>& primitives, const Ray& ray) {
    Hit hit{ray.tMax, VKP_NO_HIT, glm::vec2(0.0f), VKP_NO_INSTANCE};
    const shared::TriangleRay triangleRay = shared::makeTriangleRay(ray.origin, ray.direction);
    for (uint32_t i = 0; i < primitives.size(); ++i) {
        const BvhPrimitive& p = primitives[i];
        float t;
        glm::vec2 bary(0.0f);
        const bool found =
            p.kind == VKP_PRIMITIVE_SPHERE
                ? shared::intersectSphere(ray.origin, ray.direction, p.p0, p.p1.x, hit.t, t)
                : shared::intersectTriangle(triangleRay, p.p0, p.p1, p.p2, hit.t, t, bary);
        if (found) hit = Hit{t, i, bary, VKP_NO_INSTANCE};
    }
    return hit;
}

// Runs f(i) for i in [0, n) on every hardware thread.
template <typename F>
void parallelFor(size_t n, F f) {
    const size_t threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (size_t w = 0; w < threads; ++w)
        pool.emplace_back([&, w] {
            for (size_t i = w; i < n; i += threads) f(i);
        });
    for (std::thread& t : pool) t.join();
}

inline std::vector<Hit> bruteForceClosest(const std::vector<BvhPrimitive>& primitives,
                                          const std::vector<Ray>& rays) {
    std::vector<Hit> hits(rays.size());
    parallelFor(rays.size(), [&](size_t i) { hits[i] = bruteForceClosest(primitives, rays[i]); });
    return hits;
}

// ---- comparing hits ----------------------------------------------------------------

// Equality: the same primitive with t within 1e-5 relative (a GPU may round a
// division differently). Ties: when two primitives are hit at the same
// distance (to 1e-5) either may be reported; a ray counts as a tie when the
// CPU confirms that the reported primitive is hit at the expected distance.
constexpr float RELATIVE_T_TOLERANCE = 1e-5f;

struct Comparison {
    size_t hits = 0;
    size_t ties = 0;
    size_t mismatches = 0;
    std::string first;
};

inline bool closeT(float a, float b) {
    return std::abs(a - b) <= RELATIVE_T_TOLERANCE * std::max(std::abs(b), 1e-30f);
}

inline Comparison compareHits(const vkpath::bvh::BvhBuild& build, const std::vector<Ray>& rays,
                              const std::vector<Hit>& got, const std::vector<Hit>& expected) {
    Comparison c;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit& g = got[i];
        const Hit& e = expected[i];
        bool ok = true;
        if (e.primitive == VKP_NO_HIT || g.primitive == VKP_NO_HIT) {
            ok = e.primitive == g.primitive;
        } else if (g.primitive == e.primitive) {
            ok = closeT(g.t, e.t);
        } else {
            float t;
            glm::vec2 bary;
            ok = g.primitive < build.primitives.size() &&
                 intersectPrimitive(build.primitives[g.primitive], rays[i], FLT_MAX_VALUE, t,
                                    bary) &&
                 closeT(t, e.t) && closeT(g.t, e.t);
            c.ties += ok;
        }
        c.hits += e.primitive != VKP_NO_HIT;
        if (!ok && c.mismatches++ == 0)
            c.first = "ray " + std::to_string(i) + ": got primitive " +
                      std::to_string(g.primitive) + " t " + std::to_string(g.t) + ", expected " +
                      std::to_string(e.primitive) + " t " + std::to_string(e.t);
    }
    return c;
}

// ---- instancing: one object placed, or its placements copied ----------------------

// Placements of the object: rotations about tilted axes, uniform and uneven
// scales, one mirror, on a grid.
inline std::vector<glm::dmat4> placements(int count) {
    std::vector<glm::dmat4> out;
    for (int k = 0; k < count; ++k) {
        glm::dmat4 m(1.0);
        m = glm::translate(m, glm::dvec3((k % 4) * 2.5 - 3.75, (k / 4) * 2.5 - 2.5, -0.5 * k));
        m = glm::rotate(m, 0.3 + 0.7 * k,
                        glm::normalize(glm::dvec3(std::cos(k), 1.0, std::sin(k))));
        glm::dvec3 scale(0.6 + 0.15 * (k % 5));
        if (k % 3 == 1) scale *= glm::dvec3(1.4, 1.0, 0.7);
        if (k == 5) scale.x = -scale.x;  // a mirror image
        out.push_back(glm::scale(m, scale));
    }
    return out;
}

// The scene with the two meshes of one object placed `count` times, plus a
// world-space triangle soup and spheres: instanced, or flattened (each
// placement a copy with its vertices placed in double and, under a mirror,
// its winding swapped, as host/scene/gltf_meshes.cpp does).
inline scene::Scene placedScene(int count, bool instanced) {
    scene::Scene s = emptyScene();
    addTriangleSoup(s, 300, 0.4f, 7);
    addSphereField(s, 20, 0.1f, 0.3f, 11);
    const scene::Mesh parts[2] = {icosphere(3, 1.0f, vec3(0.0f)), tessellatedCube(6)};
    const std::vector<glm::dmat4> where = placements(count);
    if (instanced) {
        // Two objects: the sphere and the cube together, and the cube alone
        // (every third placement).
        const auto first = uint32_t(s.meshes.size());
        for (scene::Mesh part : parts) {
            part.instanced = true;
            s.meshes.push_back(std::move(part));
        }
        for (int k = 0; k < count; ++k) {
            const bool cubeOnly = k % 3 == 2;
            s.instances.push_back({"instance " + std::to_string(k), first + (cubeOnly ? 1u : 0u),
                                   cubeOnly ? 1u : 2u, where[size_t(k)]});
        }
        return s;
    }
    for (size_t k = 0; k < where.size(); ++k) {
        const glm::dmat4& m = where[k];
        const bool mirror = glm::determinant(glm::dmat3(m)) < 0.0;
        for (size_t i = k % 3 == 2 ? 1 : 0; i < 2; ++i) {
            scene::Mesh part = parts[i];
            for (glm::vec3& p : part.positions) p = glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
            if (mirror)
                for (glm::uvec3& t : part.triangles) std::swap(t.y, t.z);
            s.meshes.push_back(std::move(part));
        }
    }
    return s;
}

// ---- the GPU trace kernels -------------------------------------------------------

class GpuTracer {
  public:
    // byAddress: the kernels read the BVH through buffer device addresses (the
    // path of scenes beyond maxStorageBufferRange) instead of bindings.
    // traversal: RayQuery traces by the device's acceleration structures
    // (every triangle opaque).
    GpuTracer(vk::Context& context, const vkpath::bvh::BvhBuild& build, bool byAddress = false,
              vkpath::bvh::Traversal traversal = vkpath::bvh::Traversal::Compute)
        : m_context(context),
          m_bvh(upload(context, build, byAddress, traversal)),
          m_closest(context, kernel("bvh_closest", build, traversal), options(build, byAddress)),
          m_anyHit(context, kernel("bvh_anyhit", build, traversal), options(build, byAddress)) {}

    std::vector<Hit> closest(const std::vector<Ray>& rays) {
        vk::Buffer rayBuffer = vk::Buffer::fromSpan(m_context, std::span(rays));
        vk::Buffer hitBuffer(m_context, rays.size() * sizeof(Hit));
        m_lastMilliseconds = m_closest.dispatch(
            static_cast<uint32_t>(rays.size()),
            {{VKP_TRACE_BINDING_NODES, &m_bvh.nodeBinding()},
             {VKP_TRACE_BINDING_PRIMITIVES, &m_bvh.primitiveBinding()},
             {VKP_TRACE_BINDING_RAYS, &rayBuffer},
             {VKP_TRACE_BINDING_RESULTS, &hitBuffer}},
            shared::TracePush{static_cast<uint32_t>(rays.size()), m_bvh.addresses()});
        return hitBuffer.download<Hit>();
    }

    std::vector<uint32_t> occluded(const std::vector<Ray>& rays) {
        vk::Buffer rayBuffer = vk::Buffer::fromSpan(m_context, std::span(rays));
        vk::Buffer flagBuffer(m_context, rays.size() * sizeof(uint32_t));
        m_lastMilliseconds = m_anyHit.dispatch(
            static_cast<uint32_t>(rays.size()),
            {{VKP_TRACE_BINDING_NODES, &m_bvh.nodeBinding()},
             {VKP_TRACE_BINDING_PRIMITIVES, &m_bvh.primitiveBinding()},
             {VKP_TRACE_BINDING_RAYS, &rayBuffer},
             {VKP_TRACE_BINDING_RESULTS, &flagBuffer}},
            shared::TracePush{static_cast<uint32_t>(rays.size()), m_bvh.addresses()});
        return flagBuffer.download<uint32_t>();
    }

    double lastMilliseconds() const { return m_lastMilliseconds; }

  private:
    static vkpath::bvh::GpuBvh upload(vk::Context& context, const vkpath::bvh::BvhBuild& build,
                                      bool byAddress, vkpath::bvh::Traversal traversal) {
        vkpath::bvh::GpuBvh gpu = vkpath::bvh::uploadBvh(context, build, byAddress);
        if (traversal == vkpath::bvh::Traversal::RayQuery)
            vkpath::bvh::addAccelerationStructures(context, gpu, build, {});
        return gpu;
    }

    // The trace kernel for the tree and the traversal (cmake/shaders.cmake).
    static std::string kernel(const char* name, const vkpath::bvh::BvhBuild& build,
                              vkpath::bvh::Traversal traversal) {
        return vkpath::bvh::tracingKernel(name, traversal, build.stats.instances > 0);
    }

    // Specialised as a render's kernels are to the tree's depth (whether the
    // stack may spill to an array) and its instances; every other feature bit set.
    static vk::KernelOptions options(const vkpath::bvh::BvhBuild& build, bool byAddress) {
        const uint64_t features =
            (VKP_FEATURES_ALL & ~(VKP_FEATURE_DEEP_BVH | VKP_FEATURE_INSTANCES)) |
            vkpath::bvh::traversalFeatures(build);
        const auto constants = vkpath::wavefront::featureConstants(features);
        return vk::KernelOptions{.specialization = {vkpath::bvh::sceneAccessConstant(byAddress),
                                                    constants[0], constants[1]}};
    }

    vk::Context& m_context;
    vkpath::bvh::GpuBvh m_bvh;
    vk::Kernel m_closest;
    vk::Kernel m_anyHit;
    double m_lastMilliseconds = 0;
};

}  // namespace vkpath::test::bvh
