// The wavefront's intersect and shadow stages dispatched on their own through
// the kernel harness, on the bunny and a mixed soup of triangles and spheres:
// they read their rays through the queues the way the renderer lays them out,
// and give the CPU traversal's closest hits and visibility.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <random>

#include "bvh/bvh_test_util.h"
#include "scene/load.h"
#include "shared/scene_addresses.h"
#include "shared/scene_data.h"
#include "shared/wavefront.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

constexpr uint32_t SLOTS = 20000;  // paths in flight (W)
constexpr Hit UNTOUCHED{-1.0f, 0xdeadbeefu, glm::vec2(0.0f)};

// Slots queued for a bounce: a shuffled two thirds of [0, SLOTS), so the
// stage must follow the queue, and leave every other slot alone.
std::vector<uint32_t> queuedSlots(uint32_t seed) {
    std::vector<uint32_t> slots(SLOTS);
    std::iota(slots.begin(), slots.end(), 0u);
    std::mt19937 rng(seed);
    std::shuffle(slots.begin(), slots.end(), rng);
    slots.resize(SLOTS * 2 / 3);
    return slots;
}

struct StageScene {
    std::string name;
    scene::Scene scene;
};

// 0: the Scotty3D bunny (the assignment's scenes); 1: triangles and spheres
// made here. Each loaded once, on first use.
const StageScene& stageScene(size_t index) {
    if (index == 0) {
        static const StageScene bunny{"bunny", scene::loadScene(test::sharedScene("bunny.dae"))};
        return bunny;
    }
    static const StageScene mixed{"mixed", [] {
                                      scene::Scene s = emptyScene();
                                      addTriangleSoup(s, 3000, 0.1f, 5);
                                      addSphereField(s, 300, 0.01f, 0.1f, 6);
                                      return s;
                                  }()};
    return mixed;
}

// Dispatches a stage with `given` bound, and a placeholder at every other
// binding it declares: the scene's materials and textures, which only the
// alpha test reads, and a SceneInfo of zeros (alphaTested 0) turns it off.
void dispatchStage(vk::Kernel& kernel, uint32_t invocations,
                   std::map<uint32_t, const vk::Buffer*> given, const shared::WavePush& push) {
    vk::Context& context = test::context();
    // One texel: some of the bindings are texel buffers.
    const vk::Buffer placeholder(context, 16, vk::MemoryKind::DeviceLocal, "placeholder");
    for (const vk::SpirvBinding& b : kernel.reflection().bindings)
        given.try_emplace(b.binding, &placeholder);
    const vk::DescriptorSet set = kernel.bindDeclared(given);
    context.submit([&](VkCommandBuffer cmd) {
        kernel.record(cmd, set, invocations, std::as_bytes(std::span(&push, 1)));
    });
}

class Stage : public testing::TestWithParam<size_t> {
  protected:
    void SetUp() override {
        if (GetParam() == 0) VKPATH_SKIP_WITHOUT_SHARED_SCENES();
        m_scene = &stageScene(GetParam());
        m_build = buildChecked(m_scene->scene);
        // Rays around the geometry's bounds, half of them aimed at a primitive.
        const auto [lo, hi] = bounds();
        m_rays = randomRays(m_build, SLOTS, 17, lo - (hi - lo) * 0.2f, hi + (hi - lo) * 0.2f);
    }

    std::pair<vec3, vec3> bounds() const {
        vec3 lo(FLT_MAX_VALUE), hi(-FLT_MAX_VALUE);
        for (const BvhPrimitive& p : m_build.primitives) {
            const vec3 r = p.kind == VKP_PRIMITIVE_SPHERE ? vec3(p.p1.x) : vec3(0.0f);
            lo = glm::min(
                lo,
                glm::min(p.p0 - r, p.kind == VKP_PRIMITIVE_SPHERE ? p.p0 : glm::min(p.p1, p.p2)));
            hi = glm::max(
                hi,
                glm::max(p.p0 + r, p.kind == VKP_PRIMITIVE_SPHERE ? p.p0 : glm::max(p.p1, p.p2)));
        }
        return {lo, hi};
    }

    const StageScene* m_scene = nullptr;
    vkpath::bvh::BvhBuild m_build;
    std::vector<Ray> m_rays;
};

// At an odd bounce the stage reads ray queue 1, at queues[W + entry].
TEST_P(Stage, IntersectGivesTheCpuClosestHitOfEveryQueuedRay) {
    vk::Context& context = test::context();
    const vkpath::bvh::GpuBvh bvh = vkpath::bvh::uploadBvh(context, m_build);
    const shared::SceneAddresses noAddresses{};
    vk::Buffer addresses = vk::Buffer::fromSpan(context, std::span(&noAddresses, 1));
    vk::Buffer rays = vk::Buffer::fromSpan(context, std::span(m_rays));
    const std::vector<Hit> before(SLOTS, UNTOUCHED);
    vk::Buffer hits = vk::Buffer::fromSpan(context, std::span(before));
    const std::vector<uint32_t> slots = queuedSlots(3);
    std::vector<uint32_t> queueData(3 * SLOTS, 0xffffffffu);
    std::copy(slots.begin(), slots.end(), queueData.begin() + SLOTS);
    vk::Buffer queues = vk::Buffer::fromSpan(context, std::span(queueData));
    shared::QueueCounters counterData{};
    counterData.rayCount0 = 0;  // the even queue is empty: reading it would do nothing
    counterData.rayCount1 = uint32_t(slots.size());
    vk::Buffer counters = vk::Buffer::fromSpan(context, std::span(&counterData, 1));

    const shared::SceneInfo infoData{};
    vk::Buffer info = vk::Buffer::fromSpan(context, std::span(&infoData, 1));

    vk::Kernel intersect(context, "intersect",
                         {.specialization = {vkpath::bvh::sceneAccessConstant(false)}});
    dispatchStage(intersect, uint32_t(slots.size()),
                  {{VKP_WF_SCENE_INFO, &info},
                   {VKP_WF_BVH_NODES, &bvh.nodeBinding()},
                   {VKP_WF_BVH_PRIMITIVES, &bvh.primitiveBinding()},
                   {VKP_WF_SCENE_ADDRESSES, &addresses},
                   {VKP_WF_RAYS, &rays},
                   {VKP_WF_HITS, &hits},
                   {VKP_WF_QUEUES, &queues},
                   {VKP_WF_COUNTERS, &counters}},
                  shared::WavePush{0, 0, SLOTS, /*bounce*/ 1, 0});
    const std::vector<Hit> got = hits.download<Hit>();

    const shared::BvhView view{m_build.traversalNodes, m_build.primitives};
    std::vector<Ray> queuedRays;
    std::vector<Hit> queuedHits, expected;
    std::vector<bool> queued(SLOTS, false);
    for (uint32_t slot : slots) {
        queued[slot] = true;
        queuedRays.push_back(m_rays[slot]);
        queuedHits.push_back(got[slot]);
        expected.push_back(view.bvhClosestHit(m_rays[slot]));
    }
    const Comparison c = compareHits(m_build, queuedRays, queuedHits, expected);
    EXPECT_EQ(c.mismatches, 0u) << c.first;
    EXPECT_LE(c.ties, queuedRays.size() / 1000);
    EXPECT_GT(c.hits, queuedRays.size() / 3) << "most rays aimed at a primitive hit";
    size_t touched = 0;
    for (uint32_t slot = 0; slot < SLOTS; ++slot)
        if (!queued[slot])
            touched += got[slot].primitive != UNTOUCHED.primitive || got[slot].t != UNTOUCHED.t;
    EXPECT_EQ(touched, 0u) << "slots not in the queue were written";
}

// Each queued path has two shadow rays with a contribution (one of them zero,
// which the stage must skip); the stage adds the unoccluded ones to the path's
// radiance, in order, and leaves unqueued paths alone.
TEST_P(Stage, ShadowAddsExactlyTheUnoccludedContributions) {
    constexpr uint32_t LIGHT_SAMPLES = 2;
    vk::Context& context = test::context();
    const vkpath::bvh::GpuBvh bvh = vkpath::bvh::uploadBvh(context, m_build);
    const shared::SceneAddresses noAddresses{};
    vk::Buffer addresses = vk::Buffer::fromSpan(context, std::span(&noAddresses, 1));
    shared::SceneInfo infoData{};
    infoData.lightSamples = LIGHT_SAMPLES;
    vk::Buffer info = vk::Buffer::fromSpan(context, std::span(&infoData, 1));

    // Shadow rays: segments of the random rays, ending at a random fraction of
    // the distance to the scene's far side, so some are blocked and some not.
    const auto [lo, hi] = bounds();
    const float span = glm::length(hi - lo);
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> shadowRayData(SLOTS * LIGHT_SAMPLES);
    std::vector<glm::vec3> contributionData(SLOTS * LIGHT_SAMPLES), radianceData(SLOTS);
    for (uint32_t i = 0; i < SLOTS * LIGHT_SAMPLES; ++i) {
        shadowRayData[i] = m_rays[(i * 7919u) % SLOTS];
        shadowRayData[i].tMax = span * u(rng);
        contributionData[i] =
            i % 5 == 4 ? glm::vec3(0.0f) : glm::vec3(u(rng), u(rng), u(rng)) + 0.01f;
    }
    for (uint32_t slot = 0; slot < SLOTS; ++slot)
        radianceData[slot] = glm::vec3(float(slot), 0.5f, 0.25f);
    vk::Buffer shadowRays = vk::Buffer::fromSpan(context, std::span(shadowRayData));
    vk::Buffer contributions = vk::Buffer::fromSpan(context, std::span(contributionData));
    vk::Buffer radiance = vk::Buffer::fromSpan(context, std::span(radianceData));
    const std::vector<uint32_t> slots = queuedSlots(4);
    std::vector<uint32_t> queueData(3 * SLOTS, 0xffffffffu);
    std::copy(slots.begin(), slots.end(), queueData.begin() + 2 * SLOTS);  // the shadow queue
    vk::Buffer queues = vk::Buffer::fromSpan(context, std::span(queueData));
    shared::QueueCounters counterData{};
    counterData.shadowCount = uint32_t(slots.size());
    vk::Buffer counters = vk::Buffer::fromSpan(context, std::span(&counterData, 1));

    vk::Kernel shadow(context, "shadow",
                      {.specialization = {vkpath::bvh::sceneAccessConstant(false)}});
    dispatchStage(shadow, uint32_t(slots.size()),
                  {{VKP_WF_SCENE_INFO, &info},
                   {VKP_WF_BVH_NODES, &bvh.nodeBinding()},
                   {VKP_WF_BVH_PRIMITIVES, &bvh.primitiveBinding()},
                   {VKP_WF_SCENE_ADDRESSES, &addresses},
                   {VKP_WF_RADIANCE, &radiance},
                   {VKP_WF_QUEUES, &queues},
                   {VKP_WF_COUNTERS, &counters},
                   {VKP_WF_SHADOW_RAYS, &shadowRays},
                   {VKP_WF_SHADOW_RADIANCE, &contributions}},
                  shared::WavePush{0, 0, SLOTS, 0, 0});
    const std::vector<glm::vec3> got = radiance.download<glm::vec3>();

    const shared::BvhView view{m_build.traversalNodes, m_build.primitives};
    std::vector<glm::vec3> expected = radianceData;
    size_t blocked = 0, open = 0;
    for (uint32_t slot : slots) {
        glm::vec3 sum(0.0f);
        for (uint32_t j = 0; j < LIGHT_SAMPLES; ++j) {
            const uint32_t index = slot * LIGHT_SAMPLES + j;
            if (contributionData[index] == glm::vec3(0.0f)) continue;
            const bool occluded = view.bvhOccluded(shadowRayData[index]);
            (occluded ? blocked : open)++;
            if (!occluded) sum += contributionData[index];
        }
        expected[slot] += sum;
    }
    size_t mismatches = 0;
    for (uint32_t slot = 0; slot < SLOTS; ++slot) mismatches += got[slot] != expected[slot];
    EXPECT_EQ(mismatches, 0u)
        << "radiance differs from the CPU's (bit for bit: the same additions in the same order)";
    EXPECT_GT(blocked, slots.size() / 20);
    EXPECT_GT(open, slots.size() / 20);
}

INSTANTIATE_TEST_SUITE_P(Scenes, Stage, testing::Values(0, 1),
                         [](const testing::TestParamInfo<size_t>& p) {
                             return p.param == 0 ? "bunny" : "mixed";
                         });

}  // namespace
