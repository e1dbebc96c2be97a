// Tracing by the device's acceleration structures (--traversal rayquery,
// shaders/shared/bvh_ray_query.h) against the kernels' own traversal
// (shaders/shared/bvh_traverse.h), both on the test device (lavapipe in CI,
// whose ray queries are Mesa's). Rays from random points and rays spawned off
// the surfaces they hit, on a triangle soup with spheres and on the same
// scene with an object placed twelve times by instances (rotated, unevenly
// scaled, one mirrored). A hit on the same primitive must be the same hit bit
// for bit: the ray-query kernel tests the device's primitive again with the
// compute traversal's own test. Another primitive is allowed where the two
// may disagree (two primitives at the same distance, which the compute
// traversal breaks by index and the device by its own order; a ray that
// grazes an edge, where the device's test and ours round differently); their
// share is bounded below beside what it measured.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <utility>

#include "bvh_test_util.h"
#include "scene/load.h"
#include "shared/intersect.h"
#include "support/test_context.h"
#include "wavefront/gpu_scene.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

struct Differences {
    size_t rays = 0, hits = 0;
    size_t otherPrimitive = 0;  // another primitive or instance, or a hit against a miss
    size_t otherDetail = 0;     // the same primitive at another t or barycentrics
    size_t occlusion = 0;       // any-hit answers that differ
    std::string first;
};

Differences compare(const bvh::BvhBuild& build, const std::vector<Ray>& rays) {
    GpuTracer compute(test::context(), build, false, bvh::Traversal::Compute);
    GpuTracer rayQuery(test::context(), build, false, bvh::Traversal::RayQuery);
    const std::vector<Hit> a = compute.closest(rays);
    const std::vector<Hit> b = rayQuery.closest(rays);
    const std::vector<uint32_t> oa = compute.occluded(rays);
    const std::vector<uint32_t> ob = rayQuery.occluded(rays);
    Differences d;
    d.rays = rays.size();
    for (size_t i = 0; i < rays.size(); ++i) {
        d.hits += a[i].primitive != VKP_NO_HIT;
        d.occlusion += (oa[i] != 0) != (ob[i] != 0);
        if (a[i].primitive != b[i].primitive || a[i].instance != b[i].instance) {
            if (d.otherPrimitive++ == 0)
                d.first = "ray " + std::to_string(i) + ": compute " +
                          std::to_string(a[i].primitive) + "/" + std::to_string(a[i].instance) +
                          " t " + std::to_string(a[i].t) + ", rayquery " +
                          std::to_string(b[i].primitive) + "/" + std::to_string(b[i].instance) +
                          " t " + std::to_string(b[i].t);
        } else if (std::memcmp(&a[i], &b[i], sizeof(Hit)) != 0) {
            ++d.otherDetail;
        }
    }
    return d;
}

// Rays leaving the surfaces that `rays` hit (`hits`), and where each left from.
struct Spawned {
    std::vector<Ray> rays;
    std::vector<std::pair<uint32_t, uint32_t>> from;  // (primitive, instance)
};

// From every hit of `hits`, a ray leaving the surface (offset as the
// integrator spawns one, shared/intersect.h spawnRay) to a random side.
// Instanced hits are placed in the world first, as shading places them.
Spawned spawnedRays(const bvh::BvhBuild& build, const std::vector<Ray>& rays,
                    const std::vector<Hit>& hits, uint32_t seed) {
    std::mt19937 rng(seed);
    Spawned out;
    for (size_t i = 0; i < rays.size(); ++i) {
        if (hits[i].primitive == VKP_NO_HIT) continue;
        const BvhPrimitive object = build.primitives[hits[i].primitive];
        BvhPrimitive p = object;
        shared::InstanceTransform x{};
        const bool instanced = hits[i].instance != VKP_NO_INSTANCE;
        if (instanced) {
            const uint32_t record = build.primitives[hits[i].instance].id;
            for (uint32_t k = 0; k < 3; ++k) {
                std::memcpy(&x.worldToObject[k], &build.traversalNodes[record + k],
                            sizeof(glm::vec4));
                std::memcpy(&x.objectToWorld[k], &build.traversalNodes[record + 3 + k],
                            sizeof(glm::vec4));
            }
            p.p0 = shared::transformPoint(x.objectToWorld, p.p0);
            p.p1 = shared::transformPoint(x.objectToWorld, p.p1);
            p.p2 = shared::transformPoint(x.objectToWorld, p.p2);
        }
        shared::SurfacePoint sp = shared::surfacePoint(p, rays[i], hits[i]);
        if (instanced) sp.spawnOffset = shared::instanceSpawnOffset(x, sp.position, object);
        vec3 d = randomDirection(rng);
        if (glm::dot(d, sp.normal) * (rng() % 2 == 0 ? 1.0f : -1.0f) < 0.0f) d = -d;
        out.rays.push_back(shared::spawnRay(sp, d, FLT_MAX_VALUE, uint32_t(i)));
        out.from.emplace_back(hits[i].primitive, hits[i].instance);
    }
    return out;
}

// Spawned rays whose closest hit is the triangle they leave (a plane: no ray
// leaving it meets it again; one leaving a sphere inward meets its far side).
size_t selfHits(const bvh::BvhBuild& build, const Spawned& spawned, const std::vector<Hit>& hits) {
    size_t n = 0;
    for (size_t i = 0; i < hits.size(); ++i)
        n += build.primitives[spawned.from[i].first].kind == VKP_PRIMITIVE_TRIANGLE &&
             hits[i].primitive == spawned.from[i].first &&
             hits[i].instance == spawned.from[i].second;
    return n;
}

void expectAgreement(const bvh::BvhBuild& build, const std::vector<Ray>& rays,
                     double maxOtherShare) {
    const Differences d = compare(build, rays);
    EXPECT_GT(d.hits, d.rays / 4);
    EXPECT_EQ(d.otherDetail, 0u) << "of " << d.rays;
    EXPECT_LE(double(d.otherPrimitive), maxOtherShare * double(d.rays))
        << d.otherPrimitive << " of " << d.rays << "; first: " << d.first;
    EXPECT_LE(double(d.occlusion), maxOtherShare * double(d.rays))
        << d.occlusion << " of " << d.rays;
    std::printf("%zu rays, %zu hits: %zu on another primitive, %zu other detail, %zu occlusion\n",
                d.rays, d.hits, d.otherPrimitive, d.otherDetail, d.occlusion);
}

// The BVH tests' object placed twelve times (flattened, then instanced) and
// assets/instances.gltf (thirty small tori placed far from the origin, in
// the render space the renderer moves a scene into).
std::vector<std::pair<std::string, bvh::BvhBuild>> scenes() {
    std::vector<std::pair<std::string, bvh::BvhBuild>> out;
    out.emplace_back("placed, flattened", buildChecked(placedScene(12, false)));
    out.emplace_back("placed, instanced", buildChecked(placedScene(12, true)));
    scene::LoadOptions on;
    on.instancing = scene::Instancing::On;
    out.emplace_back(
        "instances.gltf",
        wavefront::buildSceneTables(scene::loadScene(test::sourcePath("assets/instances.gltf"), on))
            .bvh);
    return out;
}

TEST(RayQuery, SameHitsAsTheComputeTraversal) {
    if (!test::context().info().rayQuery) GTEST_SKIP() << "the test device has no ray queries";
    for (const auto& [what, build] : scenes()) {
        SCOPED_TRACE(what);
        const std::vector<Ray> rays = randomRays(build, 20000, 3, vec3(-6.0f), vec3(6.0f));
        expectAgreement(build, rays, 0.001);
        GpuTracer compute(test::context(), build);
        const Spawned spawned = spawnedRays(build, rays, compute.closest(rays), 5);
        expectAgreement(build, spawned.rays, 0.001);
    }
}

// A ray spawned off a surface does not hit it again, in either traversal:
// on instanced meshes it starts instanceSpawnOffset farther off, for the
// traversal moves it into the object's space (without it, 9 of the 14 272
// rays spawned on instances.gltf hit the triangle they left in the compute
// traversal, and 5 by ray queries).
TEST(RayQuery, SpawnedRaysLeaveTheirSurface) {
    for (const auto& [what, build] : scenes()) {
        SCOPED_TRACE(what);
        const std::vector<Ray> rays = randomRays(build, 20000, 3, vec3(-6.0f), vec3(6.0f));
        GpuTracer compute(test::context(), build);
        const Spawned spawned = spawnedRays(build, rays, compute.closest(rays), 5);
        EXPECT_EQ(selfHits(build, spawned, compute.closest(spawned.rays)), 0u)
            << "of " << spawned.rays.size();
        if (!test::context().info().rayQuery) continue;
        GpuTracer rayQuery(test::context(), build, false, bvh::Traversal::RayQuery);
        EXPECT_EQ(selfHits(build, spawned, rayQuery.closest(spawned.rays)), 0u)
            << "of " << spawned.rays.size();
    }
}

}  // namespace
