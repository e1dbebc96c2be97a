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

#include "bvh_test_util.h"
#include "shared/intersect.h"
#include "support/test_context.h"

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

// From every hit of `hits`, a ray leaving the surface (offset as the
// integrator spawns one, shared/intersect.h spawnRay) to a random side.
// Instanced hits are placed in the world first, as shading places them.
std::vector<Ray> spawnedRays(const bvh::BvhBuild& build, const std::vector<Ray>& rays,
                             const std::vector<Hit>& hits, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<Ray> out;
    for (size_t i = 0; i < rays.size(); ++i) {
        if (hits[i].primitive == VKP_NO_HIT) continue;
        BvhPrimitive p = build.primitives[hits[i].primitive];
        if (hits[i].instance != VKP_NO_INSTANCE) {
            const uint32_t record = build.primitives[hits[i].instance].id;
            glm::vec4 rows[3];
            for (uint32_t k = 0; k < 3; ++k)
                std::memcpy(&rows[k], &build.traversalNodes[record + 3 + k], sizeof(glm::vec4));
            p.p0 = shared::transformPoint(rows, p.p0);
            p.p1 = shared::transformPoint(rows, p.p1);
            p.p2 = shared::transformPoint(rows, p.p2);
        }
        const shared::SurfacePoint sp = shared::surfacePoint(p, rays[i], hits[i]);
        vec3 d = randomDirection(rng);
        if (glm::dot(d, sp.normal) * (rng() % 2 == 0 ? 1.0f : -1.0f) < 0.0f) d = -d;
        out.push_back(shared::spawnRay(sp, d, FLT_MAX_VALUE, uint32_t(i)));
    }
    return out;
}

void expectAgreement(const bvh::BvhBuild& build, const std::vector<Ray>& rays,
                     double maxOtherShare) {
    const Differences d = compare(build, rays);
    EXPECT_GT(d.hits, d.rays / 3);
    EXPECT_EQ(d.otherDetail, 0u) << "of " << d.rays;
    EXPECT_LE(double(d.otherPrimitive), maxOtherShare * double(d.rays))
        << d.otherPrimitive << " of " << d.rays << "; first: " << d.first;
    EXPECT_LE(double(d.occlusion), maxOtherShare * double(d.rays))
        << d.occlusion << " of " << d.rays;
    std::printf("%zu rays, %zu hits: %zu on another primitive, %zu other detail, %zu occlusion\n",
                d.rays, d.hits, d.otherPrimitive, d.otherDetail, d.occlusion);
}

TEST(RayQuery, SameHitsAsTheComputeTraversal) {
    if (!test::context().info().rayQuery) GTEST_SKIP() << "the test device has no ray queries";
    for (const bool instanced : {false, true}) {
        SCOPED_TRACE(instanced ? "instanced" : "flat");
        const scene::Scene s = placedScene(12, instanced);
        const bvh::BvhBuild build = buildChecked(s);
        const std::vector<Ray> rays = randomRays(build, 20000, 3, vec3(-6.0f), vec3(6.0f));
        expectAgreement(build, rays, 0.001);
        GpuTracer compute(test::context(), build);
        const std::vector<Ray> spawned = spawnedRays(build, rays, compute.closest(rays), 5);
        expectAgreement(build, spawned, 0.001);
    }
}

}  // namespace
