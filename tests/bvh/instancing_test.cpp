// Instancing's two-level tree (shaders/shared/bvh.h): meshes kept once in
// their own space, a tree each, placed by instance primitives of the scene's
// tree. The same scene is built twice, instanced and with every placement
// copied into world space as the glTF importer copies it, and rays are traced
// through both:
//   - the instanced build passes the integrity check, one bottom-level tree
//     per placed range of meshes, whatever the number of placements;
//   - the binary traversal on the CPU, the CPU reference's eight-wide tree
//     and the GPU's trace kernels return the same hits bit for bit (t,
//     primitive, barycentrics, instance), and the same any-hit answers: they
//     move the ray into an instance's space with the same operations;
//   - those hits are the flattened scene's up to rounding: the same placed
//     triangle at the same point (within a few ulps of the scene's size
//     across the surface), except on rays that graze an edge or a
//     silhouette, where a ray moved into an instance's space (rounded) and a
//     triangle moved into the world's (rounded differently) may disagree
//     about a hit. Both bounds are below, each beside what it measured.
#include <gtest/gtest.h>

#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/component_wise.hpp>
#include <map>

#include "bvh/wide_bvh.h"
#include "bvh_test_util.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

// Rays whose instanced hit may differ from the flattened scene's (a hit in
// one and a miss in the other, or another triangle across a shared edge):
// measured 0 of 20 000; bounded at 0.1%, rays within a few ulps of an edge
// or a silhouette among rays aimed at triangles of a few hundred to a
// thousand ulps across.
constexpr double MAX_DIFFERING_SHARE = 0.001;
// How far the two hit points may lie apart across the surface, relative to
// the largest coordinate of the ray's origin and the hit: a copy's vertices
// are the placed vertices rounded to float, the instanced hit is on the
// object's vertices, met by a ray rounded into the object's space, each a
// few ulps (2^-23) of that magnitude. Measured: at most 5.6e-7 (5 ulps);
// bounded at 2^-18 (32 ulps).
constexpr float POSITION_TOLERANCE = 0x1p-18f;

bool sameHit(const Hit& a, const Hit& b) {
    return std::memcmp(&a, &b, sizeof(Hit)) == 0;
}

TEST(Instancing, OneTreePerObjectWhateverThePlacements) {
    for (const int count : {1, 3, 24}) {
        const scene::Scene s = placedScene(count, true);
        const bvh::BvhBuild build = buildChecked(s);
        // The sphere with the cube, and from three placements on the cube alone.
        ASSERT_EQ(build.objects.size(), count >= 3 ? 2u : 1u);
        EXPECT_EQ(build.stats.instances, size_t(count));
        // The objects' triangles once each: the soup's 300, the sphere's
        // 1280, the cube's 6 x 72 (once with the sphere, once alone).
        EXPECT_EQ(build.stats.triangles, 300u + 1280u + 6u * 72u + (count >= 3 ? 6u * 72u : 0u));
        EXPECT_EQ(build.objects[0].primitiveCount, 1280u + 6u * 72u);
        EXPECT_EQ(bvh::traversalFeatures(build) & VKP_FEATURE_INSTANCES, VKP_FEATURE_INSTANCES);
    }
}

TEST(Instancing, SingularAndEmptyPlacementsAreLeftOut) {
    scene::Scene s = placedScene(2, true);
    s.instances.push_back(
        {"flat", s.instances[0].firstMesh, 2, glm::scale(glm::dmat4(1.0), glm::dvec3(1, 0, 1))});
    s.instances.push_back(
        {"huge", s.instances[0].firstMesh, 2, glm::scale(glm::dmat4(1.0), glm::dvec3(1e300))});
    const bvh::BvhBuild build = buildChecked(s);
    EXPECT_EQ(build.stats.instances, 2u);
    EXPECT_EQ(build.stats.degenerateInstances, 2u);
}

TEST(Instancing, TraversalsAgreeBitForBitAndWithTheFlattenedScene) {
    const int count = 12;
    const scene::Scene instancedScene = placedScene(count, true);
    const scene::Scene flatScene = placedScene(count, false);
    const bvh::BvhBuild instanced = buildChecked(instancedScene);
    const bvh::BvhBuild flat = buildChecked(flatScene);
    const std::vector<Ray> rays = randomRays(flat, 20000, 3, vec3(-6.0f), vec3(6.0f));

    // Which flattened triangle each (instance, object triangle) is: the
    // copies follow the soup, placement after placement, in mesh order
    // (every third placement the cube alone).
    const uint32_t soup = 300, sphere = 1280;
    std::vector<uint32_t> flatStart(count);
    for (int k = 0, next = int(soup); k < count; ++k) {
        flatStart[size_t(k)] = uint32_t(next);
        next += k % 3 == 2 ? 6 * 72 : int(sphere) + 6 * 72;
    }
    // The instance records follow the nodes in scene order: a record's place
    // among them is its placement.
    uint32_t firstRecord = UINT32_MAX;
    for (const auto& p : instanced.primitives)
        if (p.kind == VKP_PRIMITIVE_INSTANCE) firstRecord = std::min(firstRecord, p.id);
    std::map<uint32_t, uint32_t> placementOfInstance;  // instance primitive -> placement
    for (uint32_t i = 0; i < instanced.primitives.size(); ++i)
        if (instanced.primitives[i].kind == VKP_PRIMITIVE_INSTANCE)
            placementOfInstance[i] =
                (instanced.primitives[i].id - firstRecord) / VKP_INSTANCE_RECORD_TEXELS;
    auto flatTriangle = [&](const Hit& h) -> uint32_t {
        const BvhPrimitive& p = instanced.primitives[h.primitive];
        if (p.kind != VKP_PRIMITIVE_TRIANGLE) return UINT32_MAX;  // a sphere: compared by t
        if (h.instance == VKP_NO_INSTANCE) return p.id;
        const uint32_t k = placementOfInstance.at(h.instance);
        return flatStart[k] + (k % 3 == 2 ? p.id - soup - sphere : p.id - soup);
    };

    const shared::BvhView view{instanced.traversalNodes, instanced.primitives};
    const shared::BvhView flatView{flat.traversalNodes, flat.primitives};
    const bvh::WideBvh wide = bvh::collapseBvh(instanced);
    test::bvh::GpuTracer gpu(test::context(), instanced);
    const std::vector<Hit> gpuHits = gpu.closest(rays);
    const std::vector<uint32_t> gpuOccluded = gpu.occluded(rays);

    size_t hits = 0, instancedHits = 0, wideDiffers = 0, gpuDiffers = 0, occlusionDiffers = 0;
    // Against the flattened scene: rays that hit in one and miss in the
    // other, hits at another distance, hits at the same distance on another
    // triangle (a shared edge).
    size_t hitOrMiss = 0, distance = 0, neighbour = 0;
    float largestGap = 0.0f;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit binary = view.bvhClosestHit(rays[i]);
        hits += binary.primitive != VKP_NO_HIT;
        instancedHits += binary.instance != VKP_NO_INSTANCE;
        wideDiffers += !sameHit(bvh::traceWide(view, wide, rays[i], false, 0u), binary);
        gpuDiffers += !sameHit(gpuHits[i], binary);
        const bool occluded = view.bvhOccluded(rays[i]);
        occlusionDiffers +=
            occluded != (bvh::traceWide(view, wide, rays[i], true, 0u).primitive != VKP_NO_HIT) ||
            occluded != (gpuOccluded[i] != 0) || occluded != (binary.primitive != VKP_NO_HIT);

        const Hit expected = flatView.bvhClosestHit(rays[i]);
        if ((binary.primitive == VKP_NO_HIT) != (expected.primitive == VKP_NO_HIT)) {
            ++hitOrMiss;
            continue;
        }
        if (binary.primitive == VKP_NO_HIT) continue;
        const uint32_t flatId = flat.primitives[expected.primitive].kind == VKP_PRIMITIVE_TRIANGLE
                                    ? flat.primitives[expected.primitive].id
                                    : UINT32_MAX;
        // The hit points agree, across the surface, to the rounding of
        // coordinates of the scene's size (an error in t is one in position,
        // not relative to t, and along a grazing ray it is that across the
        // surface over the cosine).
        const BvhPrimitive& surface = flat.primitives[expected.primitive];
        const vec3 point = rays[i].origin + expected.t * rays[i].direction;
        const vec3 normal =
            surface.kind == VKP_PRIMITIVE_SPHERE
                ? glm::normalize(point - surface.p0)
                : glm::normalize(glm::cross(surface.p1 - surface.p0, surface.p2 - surface.p0));
        const float across =
            std::abs(glm::dot((binary.t - expected.t) * rays[i].direction, normal));
        const float magnitude =
            std::max(glm::compMax(glm::abs(rays[i].origin)), glm::compMax(glm::abs(point)));
        largestGap = std::max(largestGap, across / magnitude);
        if (across > POSITION_TOLERANCE * magnitude)
            ++distance;
        else if (flatTriangle(binary) != flatId)
            ++neighbour;
    }
    EXPECT_GT(hits, rays.size() / 2);
    EXPECT_GT(instancedHits, rays.size() / 4);
    EXPECT_EQ(wideDiffers, 0u);
    EXPECT_EQ(gpuDiffers, 0u);
    EXPECT_EQ(occlusionDiffers, 0u);
    EXPECT_EQ(distance, 0u);
    EXPECT_LE(double(hitOrMiss + neighbour), MAX_DIFFERING_SHARE * double(rays.size()))
        << hitOrMiss << " hit or miss, " << neighbour << " on a neighbour, of " << rays.size();
    std::printf(
        "instanced hits %zu of %zu rays; against the flattened scene: %zu hit or miss, "
        "%zu at another point, %zu on a neighbour; largest distance %.3g of the magnitude\n",
        instancedHits, rays.size(), hitOrMiss, distance, neighbour, largestGap);
}

}  // namespace
