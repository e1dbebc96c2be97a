// The documented edge cases of traversal and intersection (shared/intersect.h):
// degenerate primitives, rays parallel to a face or starting on a surface,
// the half-open ray interval [0, tMax) for any-hit and closest-hit, and the
// same scene at very different scales and far from the origin, including rays
// spawned off every hit (Waechter-Binder offsets), which must never hit the
// surface they leave.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "bvh_test_util.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

// ---- degenerate primitives ------------------------------------------------------

TEST(BvhRobustness, DegeneratePrimitivesAreNeverHit) {
    scene::Scene s = emptyScene();
    scene::Mesh mesh;
    mesh.name = "degenerate";
    const float nan = std::numeric_limits<float>::quiet_NaN();
    mesh.positions = {
        {0, 0, 0}, {1, 0, 0},   {1, 0, 0},  // a repeated vertex
        {0, 1, 0}, {1, 2, 1},   {2, 3, 2},  // exactly collinear
        {3, 3, 3}, {3, 3, 3},   {3, 3, 3},  // a point
        {0, 0, 2}, {nan, 0, 2}, {0, 1, 2},  // a non-finite vertex
        {5, 0, 0}, {6, 0, 0},   {5, 1, 0},  // a proper triangle, so the BVH is not empty
    };
    for (uint32_t i = 0; i < 5; ++i) mesh.triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
    s.meshes.push_back(mesh);
    s.spheres.push_back(scene::Sphere{.name = "zero", .center = {0, -2, 0}, .radius = 0.0f});
    s.spheres.push_back(scene::Sphere{.name = "negative", .center = {0, -4, 0}, .radius = -1.0f});
    s.spheres.push_back(scene::Sphere{.name = "nan", .center = {0, -6, 0}, .radius = nan});
    const bvh::BvhBuild build = buildChecked(s);
    EXPECT_EQ(build.stats.degenerateTriangles, 4u);
    EXPECT_EQ(build.stats.degenerateSpheres, 3u);
    EXPECT_EQ(build.stats.triangles, 1u);
    ASSERT_EQ(build.primitives.size(), 1u);

    // Rays from many directions at points of each degenerate primitive.
    const std::vector<vec3> targets = {{0, 0, 0}, {1, 0, 0},  {0.5f, 0, 0},       {0, 1, 0},
                                       {1, 2, 1}, {2, 3, 2},  {0.5f, 1.5f, 0.5f}, {3, 3, 3},
                                       {0, 0, 2}, {0, -2, 0}, {0, -4, 0},         {0, -4.5f, 0}};
    std::mt19937 rng(5);
    std::vector<Ray> rays;
    for (const vec3& target : targets) {
        for (int i = 0; i < 200; ++i) {
            vec3 origin = target + 3.0f * randomDirection(rng);
            if (origin.x > 4.0f) origin.x = 8.0f - origin.x;  // stay clear of the proper triangle
            // Ending just past the target: beyond it the ray could reach the proper triangle.
            rays.push_back(makeRay(origin, glm::normalize(target - origin),
                                   1.01f * glm::length(target - origin)));
        }
    }
    // Control: the proper triangle is hit.
    rays.push_back(makeRay({5.25f, 0.25f, 1.0f}, {0, 0, -1}));
    GpuTracer tracer(test::context(), build);
    const std::vector<Hit> hits = tracer.closest(rays);
    size_t hitCount = 0;
    for (size_t i = 0; i + 1 < hits.size(); ++i) hitCount += hits[i].primitive != VKP_NO_HIT;
    EXPECT_EQ(hitCount, 0u);
    EXPECT_EQ(hits.back().primitive, 0u);
    EXPECT_EQ(hits.back().t, 1.0f);
}

// ---- rays parallel to a face, rays starting on a surface -------------------------

// The square [-1, 1]^2 at height z as two triangles.
void addSquare(scene::Scene& s, float z) {
    scene::Mesh m;
    m.name = "square";
    m.positions = {{-1, -1, z}, {1, -1, z}, {1, 1, z}, {-1, 1, z}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.meshes.push_back(m);
}

TEST(BvhRobustness, RaysParallelToAFaceMissIt) {
    scene::Scene s = emptyScene();
    addSquare(s, 0.0f);
    const bvh::BvhBuild build = buildChecked(s);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-0.9f, 0.9f);
    std::vector<Ray> rays;
    for (int i = 0; i < 4000; ++i) {
        // In the plane (z = 0 exactly) and above and below it, crossing the square.
        const float z = i % 4 == 0 ? 0.0f : (i % 4 == 1 ? 0.25f : (i % 4 == 2 ? -1e-6f : 1e-30f));
        const float angle = 6.2831853f * static_cast<float>(i) / 4000.0f;
        const vec3 direction(std::cos(angle), std::sin(angle), 0.0f);
        const vec3 through(u(rng), u(rng), z);
        rays.push_back(makeRay(through - 3.0f * direction, direction));
    }
    GpuTracer tracer(test::context(), build);
    const std::vector<Hit> hits = tracer.closest(rays);
    size_t hitCount = 0;
    for (const Hit& h : hits) hitCount += h.primitive != VKP_NO_HIT;
    EXPECT_EQ(hitCount, 0u) << "a ray in or parallel to a triangle's plane must not hit it";
}

// Documented: the interval includes t = 0, so a ray starting on a surface may
// report it at t ~ 0; exactly t = 0 when the surface is axis-aligned and its
// normal's axis is the direction's dominant one. Spawned rays never do.
TEST(BvhRobustness, RaysStartingOnASurface) {
    scene::Scene s = emptyScene();
    addSquare(s, 0.0f);
    addSquare(s, 0.5f);
    const bvh::BvhBuild build = buildChecked(s);
    const shared::BvhView view{build.traversalNodes, build.primitives};
    uint32_t lower = VKP_NO_HIT;
    for (uint32_t i = 0; i < build.primitives.size(); ++i)
        if (build.primitives[i].p0.z == 0.0f && lower == VKP_NO_HIT) lower = i;

    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-0.9f, 0.9f);
    std::vector<Ray> onSurface, spawned;
    std::vector<bool> up;
    for (int i = 0; i < 4000; ++i) {
        const vec3 origin(u(rng), u(rng), 0.0f);
        vec3 d = randomDirection(rng);
        if (i % 2 == 0) {
            // Dominant z: the lower square is reported at exactly t = 0.
            d = glm::normalize(vec3(0.5f * d.x, 0.5f * d.y, d.z >= 0 ? 1.0f : -1.0f));
        }
        onSurface.push_back(makeRay(origin, d));
        // The same start spawned off the lower square, on the side d leaves to.
        const vec3 p0 = build.primitives[lower].p0, p1 = build.primitives[lower].p1,
                   p2 = build.primitives[lower].p2;
        shared::SurfacePoint sp{};
        sp.position = origin;
        sp.normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        sp.magnitude = 1.0f;
        spawned.push_back(shared::spawnRay(sp, d, FLT_MAX_VALUE, 0));
        up.push_back(d.z > 0.0f);
    }
    GpuTracer tracer(test::context(), build);
    const std::vector<Hit> hits = tracer.closest(onSurface);
    size_t wrong = 0;
    for (size_t i = 0; i < hits.size(); ++i) {
        const Hit& h = hits[i];
        const bool lowerSquare =
            h.primitive != VKP_NO_HIT && build.primitives[h.primitive].p0.z == 0.0f;
        if (i % 2 == 0)
            wrong += !(lowerSquare && h.t == 0.0f);
        else if (h.primitive != VKP_NO_HIT && lowerSquare)
            wrong += !(std::abs(h.t) <= 1e-6f);  // at t ~ 0 or not at all
        // The CPU agrees on the lower square at t = 0 for dominant z.
        if (i % 2 == 0) wrong += view.bvhClosestHit(onSurface[i]).t != 0.0f;
    }
    EXPECT_EQ(wrong, 0u);

    const std::vector<Hit> after = tracer.closest(spawned);
    size_t selfHits = 0, upperMissed = 0;
    for (size_t i = 0; i < after.size(); ++i) {
        const Hit& h = after[i];
        selfHits += h.primitive != VKP_NO_HIT && build.primitives[h.primitive].p0.z == 0.0f;
        // Upward rays through the middle of the square reach the upper one.
        const vec3 o = spawned[i].origin, d = spawned[i].direction;
        const vec3 at = o + (0.5f - o.z) / d.z * d;
        if (up[i] && std::abs(at.x) < 0.99f && std::abs(at.y) < 0.99f)
            upperMissed += h.primitive == VKP_NO_HIT || std::abs(h.t - (0.5f - o.z) / d.z) > 1e-5f;
    }
    EXPECT_EQ(selfHits, 0u);
    EXPECT_EQ(upperMissed, 0u);
}

// ---- the half-open interval [0, tMax) --------------------------------------------

TEST(BvhRobustness, TMaxExactlyAtTheHitExcludesIt) {
    scene::Scene s = emptyScene();
    addTriangleSoup(s, 300, 0.15f, 31);
    addSphereField(s, 100, 0.02f, 0.1f, 32);
    const bvh::BvhBuild build = buildChecked(s);
    const std::vector<Ray> rays = randomRays(build, 20000, 33);
    GpuTracer tracer(test::context(), build);
    const std::vector<Hit> first = tracer.closest(rays);

    std::vector<Ray> atHit, pastHit;
    std::vector<uint32_t> hitPrimitive;
    size_t spheres = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        if (first[i].primitive == VKP_NO_HIT) continue;
        Ray r = rays[i];
        r.tMax = first[i].t;
        atHit.push_back(r);
        r.tMax = std::nextafter(first[i].t, FLT_MAX_VALUE);
        pastHit.push_back(r);
        hitPrimitive.push_back(first[i].primitive);
        spheres += build.primitives[first[i].primitive].kind == VKP_PRIMITIVE_SPHERE;
    }
    ASSERT_GT(atHit.size(), 5000u);
    ASSERT_GT(spheres, 500u);

    const std::vector<uint32_t> occludedAt = tracer.occluded(atHit);
    const std::vector<uint32_t> occludedPast = tracer.occluded(pastHit);
    const std::vector<Hit> closestAt = tracer.closest(atHit);
    const std::vector<Hit> closestPast = tracer.closest(pastHit);
    size_t wrongAt = 0, wrongPast = 0, wrongClosest = 0;
    for (size_t i = 0; i < atHit.size(); ++i) {
        wrongAt += occludedAt[i] != 0u;
        wrongPast += occludedPast[i] != 1u;
        wrongClosest += closestAt[i].primitive != VKP_NO_HIT || closestAt[i].t != atHit[i].tMax;
        wrongClosest += closestPast[i].primitive != hitPrimitive[i];
    }
    EXPECT_EQ(wrongAt, 0u) << "any-hit with tMax = the hit distance must not see that hit";
    EXPECT_EQ(wrongPast, 0u) << "any-hit with tMax one ulp beyond the hit must see it";
    EXPECT_EQ(wrongClosest, 0u);
}

// ---- scale and translation ----------------------------------------------------------

// Closed icospheres and spheres, well apart, within about 50 of the origin.
scene::Scene separatedObjects() {
    scene::Scene s = emptyScene();
    std::mt19937 rng(41);
    int placed = 0;
    for (int x = -1; x <= 1; ++x) {
        for (int y = -1; y <= 1; ++y) {
            const vec3 center(30.0f * static_cast<float>(x), 30.0f * static_cast<float>(y),
                              10.0f * static_cast<float>((x + y) % 2));
            if (placed++ % 2 == 0) {
                scene::Mesh m = icosphere(2, 9.0f, center);
                m.material = 1;
                s.meshes.push_back(std::move(m));
            } else {
                s.spheres.push_back(
                    scene::Sphere{.name = "ball", .center = center, .radius = 8.0f});
            }
        }
    }
    return s;
}

scene::Scene transformed(const scene::Scene& in, float scale, vec3 offset) {
    scene::Scene s = in;
    for (scene::Mesh& m : s.meshes)
        for (vec3& p : m.positions) p = p * scale + offset;
    for (scene::Sphere& sp : s.spheres) {
        sp.center = sp.center * scale + offset;
        sp.radius *= scale;
    }
    return s;
}

struct Version {
    const char* name;
    float scale;
    vec3 offset;
};

struct SpawnCounts {
    size_t spawned = 0;
    size_t selfHits = 0;
};

// Spawns from every hit one ray to the side it came from and, for triangles,
// one to the other side; counts those that hit the primitive they leave.
SpawnCounts spawnOffHits(GpuTracer& tracer, const bvh::BvhBuild& build,
                         const std::vector<Ray>& rays, const std::vector<Hit>& hits, bool offset,
                         uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<Ray> spawned;
    std::vector<uint32_t> from;
    for (size_t i = 0; i < rays.size(); ++i) {
        if (hits[i].primitive == VKP_NO_HIT) continue;
        const BvhPrimitive& p = build.primitives[hits[i].primitive];
        shared::SurfacePoint sp = shared::surfacePoint(p, rays[i], hits[i]);
        const vec3 back = glm::dot(sp.normal, rays[i].direction) < 0.0f ? sp.normal : -sp.normal;
        for (int side = 0; side < (p.kind == VKP_PRIMITIVE_SPHERE ? 1 : 2); ++side) {
            vec3 d = randomDirection(rng);
            const vec3 n = side == 0 ? back : -back;
            if (glm::dot(d, n) < 0.0f) d = -d;
            Ray r = shared::spawnRay(sp, d, FLT_MAX_VALUE, 0);
            if (!offset) r.origin = sp.position;
            spawned.push_back(r);
            from.push_back(hits[i].primitive);
        }
    }
    const std::vector<Hit> after = tracer.closest(spawned);
    SpawnCounts c;
    c.spawned = spawned.size();
    for (size_t i = 0; i < after.size(); ++i) c.selfHits += after[i].primitive == from[i];
    return c;
}

TEST(BvhRobustness, ScaledAndTranslatedScenesHitTheSamePrimitives) {
    const scene::Scene base = separatedObjects();
    const bvh::BvhBuild baseBuild = buildChecked(base);
    const shared::BvhView baseView{baseBuild.traversalNodes, baseBuild.primitives};

    // Rays from a sphere of radius 150 around the scene at random points of
    // random primitives.
    constexpr uint32_t COUNT = 20000;
    std::mt19937 rng(43);
    std::uniform_int_distribution<size_t> pick(0, baseBuild.primitives.size() - 1);
    std::vector<Ray> rays;
    for (uint32_t i = 0; i < COUNT; ++i) {
        const vec3 origin = 150.0f * randomDirection(rng);
        rays.push_back(makeRay(
            origin, glm::normalize(pointOn(baseBuild.primitives[pick(rng)], rng) - origin)));
    }

    // A ray is robust when shifting its origin by 0.02 (five times the
    // rounding of any version: ulp(1e5) / 2 ~ 0.004) sideways in four
    // directions hits the same primitive: only robust rays must agree.
    auto key = [](const bvh::BvhBuild& b, const Hit& h) {
        return h.primitive == VKP_NO_HIT
                   ? std::make_pair(VKP_NO_HIT, VKP_NO_HIT)
                   : std::make_pair(b.primitives[h.primitive].kind, b.primitives[h.primitive].id);
    };
    std::vector<std::pair<uint32_t, uint32_t>> baseKeys(COUNT);
    std::vector<bool> robust(COUNT);
    parallelFor(COUNT, [&](size_t i) {
        const Ray& r = rays[i];
        baseKeys[i] = key(baseBuild, baseView.bvhClosestHit(r));
        const vec3 side1 = glm::normalize(glm::cross(
            r.direction, std::abs(r.direction.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0)));
        const vec3 side2 = glm::cross(r.direction, side1);
        bool same = true;
        for (const vec3& shift : {side1, -side1, side2, -side2}) {
            Ray moved = r;
            moved.origin += 0.02f * shift;
            same = same && key(baseBuild, baseView.bvhClosestHit(moved)) == baseKeys[i];
        }
        robust[i] = same;
    });
    size_t robustCount = 0;
    for (bool b : robust) robustCount += b;
    EXPECT_GT(robustCount, COUNT * 8 / 10) << "the comparison would leave out too many rays";

    const Version versions[] = {{"original", 1.0f, vec3(0.0f)},
                                {"scaled by 1e-4", 1e-4f, vec3(0.0f)},
                                {"scaled by 1e4", 1e4f, vec3(0.0f)},
                                {"translated by 1e5", 1.0f, vec3(1e5f, -1e5f, 1e5f)}};
    size_t naiveSelfHits = 0;
    for (const Version& v : versions) {
        SCOPED_TRACE(v.name);
        const scene::Scene s = transformed(base, v.scale, v.offset);
        const bvh::BvhBuild build = buildChecked(s);
        std::vector<Ray> moved = rays;
        for (Ray& r : moved) r.origin = r.origin * v.scale + v.offset;
        GpuTracer tracer(test::context(), build);
        const std::vector<Hit> hits = tracer.closest(moved);
        size_t mismatches = 0, hitCount = 0;
        for (uint32_t i = 0; i < COUNT; ++i) {
            hitCount += hits[i].primitive != VKP_NO_HIT;
            if (robust[i] && key(build, hits[i]) != baseKeys[i]) ++mismatches;
        }
        EXPECT_EQ(mismatches, 0u);
        EXPECT_GT(hitCount, COUNT * 9 / 10);

        const SpawnCounts c = spawnOffHits(tracer, build, moved, hits, true, 47);
        EXPECT_GT(c.spawned, COUNT);
        EXPECT_EQ(c.selfHits, 0u) << "spawned rays hit the surface they leave";
        naiveSelfHits += spawnOffHits(tracer, build, moved, hits, false, 47).selfHits;
    }
    // Control: the same rays started at the bare hit points do self-intersect.
    EXPECT_GT(naiveSelfHits, 0u);
}

}  // namespace
