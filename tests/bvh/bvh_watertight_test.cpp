// Watertightness: rays from inside a closed mesh aimed exactly at its edges and
// vertices (where a ray passes between triangles, and where a non-watertight
// test lets it slip through) must all hit the mesh: 10^6 rays into each of a finely
// tessellated icosphere and cube, traced on the GPU, zero escapes.
//
// The cube's faces lie in the planes of BVH boxes, so it also checks that
// box tests never cull what the triangle test would hit; a few rays start at
// the exact centre, whose directions to the face centres have zero components.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>

#include "bvh_test_util.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

constexpr uint32_t RAYS_PER_MESH = 1000000;

struct Escapes {
    size_t missed = 0;
    size_t elsewhere = 0;  // hit, but not near the aimed-at point
};

Escapes countEscapes(const AimedRays& aimed, const std::vector<Hit>& hits) {
    Escapes e;
    for (size_t i = 0; i < hits.size(); ++i) {
        if (hits[i].primitive == VKP_NO_HIT)
            ++e.missed;
        else if (std::abs(hits[i].t - aimed.distance[i]) > 1e-4f * aimed.distance[i])
            ++e.elsewhere;
    }
    return e;
}

struct MeshCase {
    const char* name;
    scene::Mesh (*make)();
};

// Names the case in test listings (instead of its bytes).
void PrintTo(const MeshCase& c, std::ostream* os) {
    *os << c.name;
}

class BvhWatertight : public testing::TestWithParam<MeshCase> {};

TEST_P(BvhWatertight, RaysAtEdgesAndVerticesNeverEscape) {
    scene::Scene s = emptyScene();
    s.meshes.push_back(GetParam().make());
    const bvh::BvhBuild build = buildChecked(s);
    const AimedRays aimed = raysAtEdgesAndVertices(s.meshes[0], RAYS_PER_MESH, 7);

    GpuTracer tracer(test::context(), build);
    const Escapes gpu = countEscapes(aimed, tracer.closest(aimed.rays));
    EXPECT_EQ(gpu.missed, 0u) << "rays escaped the closed mesh on the GPU";
    EXPECT_EQ(gpu.elsewhere, 0u);

    // The CPU runs the same code; check a tenth of the rays there too.
    AimedRays subset;
    subset.rays.assign(aimed.rays.begin(), aimed.rays.begin() + RAYS_PER_MESH / 10);
    subset.distance.assign(aimed.distance.begin(), aimed.distance.begin() + RAYS_PER_MESH / 10);
    const shared::BvhView view{build.traversalNodes, build.primitives};
    std::vector<Hit> cpuHits(subset.rays.size());
    parallelFor(subset.rays.size(),
                [&](size_t i) { cpuHits[i] = view.bvhClosestHit(subset.rays[i]); });
    const Escapes cpu = countEscapes(subset, cpuHits);
    EXPECT_EQ(cpu.missed, 0u) << "rays escaped the closed mesh on the CPU";
    EXPECT_EQ(cpu.elsewhere, 0u);
}

// The count above can fail: open a hole (drop the triangles around one
// vertex) and every ray aimed at that vertex escapes.
TEST_P(BvhWatertight, EscapesThroughAHoleAreCounted) {
    scene::Scene s = emptyScene();
    scene::Mesh mesh = GetParam().make();
    const uint32_t vertex = mesh.triangles[0].x;
    const vec3 target = mesh.positions[vertex];
    std::erase_if(mesh.triangles, [&](const glm::uvec3& t) {
        return t.x == vertex || t.y == vertex || t.z == vertex;
    });
    s.meshes.push_back(std::move(mesh));
    const bvh::BvhBuild build = buildChecked(s);
    AimedRays aimed;
    std::mt19937 rng(3);
    for (int i = 0; i < 1000; ++i) {
        const vec3 origin = randomInBox(rng, vec3(-0.5f), vec3(0.5f));
        aimed.rays.push_back(makeRay(origin, glm::normalize(target - origin)));
        aimed.distance.push_back(glm::length(target - origin));
    }
    GpuTracer tracer(test::context(), build);
    EXPECT_EQ(countEscapes(aimed, tracer.closest(aimed.rays)).missed, aimed.rays.size());
}

INSTANTIATE_TEST_SUITE_P(
    ClosedMeshes, BvhWatertight,
    testing::Values(MeshCase{"Icosphere", [] { return icosphere(5, 1.0f, vec3(0.0f)); }},
                    MeshCase{"Cube", [] { return tessellatedCube(40); }}),
    [](const testing::TestParamInfo<MeshCase>& p) { return std::string(p.param.name); });

}  // namespace
