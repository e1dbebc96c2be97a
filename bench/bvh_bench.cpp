// BVH benchmarks (Google Benchmark): build time and SAH cost for a few scene
// sizes and leaf sizes, and traversal throughput in Mrays/s (device time from
// timestamp queries) of the closest-hit and any-hit kernels for coherent
// (camera) and incoherent (diffuse bounce) rays.
//
//   build/bvh_bench [--scene=PATH.dae|.gltf|.glb ...] [benchmark flags]
//
// Generated scenes (icospheres of 20k to 1.3M triangles) always run; scenes
// loaded through scene::loadScene are added with --scene (repeatable). With no
// --scene, the Scotty3D bunny, CBbunny, plane16384 and CBspheres are used when the assignment's
// scene folder (the CMake variable VKPATH_SCENES_DIR) is there. Figures and the commands that
// produced them: docs/BENCHMARKS.md.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/bvh_view.h"
#include "bvh/gpu_bvh.h"
#include "bvh/wide_bvh.h"
#include "scene/camera.h"
#include "scene/load.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/intersect.h"
#include "vk/buffer.h"
#include "vk/context.h"
#include "vk/embedded_shaders.h"
#include "vk/kernel.h"

namespace vkpath::shaders {
std::span<const EmbeddedShader> testKernels();  // tests/kernels: bvh_closest, bvh_anyhit
}

namespace {

using namespace vkpath;
using glm::vec3;

constexpr uint32_t FILM = 512;  // coherent rays: one per pixel of a 512 x 512 film
constexpr float FLT_MAX_VALUE = 3.402823466e+38f;
// Threads per workgroup of the trace kernels, as the wavefront stages use them
// (chosen by the trace-wg benchmarks, docs/BENCHMARKS.md, "Kernel forms and
// specialisation").
constexpr uint32_t DEFAULT_WORKGROUP = 64;

// ---- scenes ---------------------------------------------------------------------

// The unit icosphere split 4^subdivisions times (20 * 4^s triangles), vertices shared.
scene::Mesh icosphere(uint32_t subdivisions) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                           {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                           {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (vec3& p : v) p = glm::normalize(p);
    std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (uint32_t s = 0; s < subdivisions; ++s) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            auto [it, inserted] = mid.emplace(key, static_cast<uint32_t>(v.size()));
            if (inserted) v.push_back(glm::normalize(v[a] + v[b]));
            return it->second;
        };
        std::vector<glm::uvec3> next;
        next.reserve(f.size() * 4);
        for (const glm::uvec3& tri : f) {
            const uint32_t a = midpoint(tri.x, tri.y), b = midpoint(tri.y, tri.z),
                           c = midpoint(tri.z, tri.x);
            next.insert(next.end(), {{tri.x, a, c}, {tri.y, b, a}, {tri.z, c, b}, {a, b, c}});
        }
        f = std::move(next);
    }
    // A bumpy surface (radius 1 +- 0.15) so the BVH has more than a sphere to fit.
    for (vec3& p : v)
        p *= 1.0f + 0.15f * std::sin(9.0f * p.x) * std::sin(7.0f * p.y) * std::sin(8.0f * p.z);
    scene::Mesh mesh;
    mesh.name = "icosphere";
    mesh.positions = std::move(v);
    mesh.triangles = std::move(f);
    return mesh;
}

struct BenchScene {
    std::string name;
    scene::Scene scene;
    shared::Camera camera;
};

BenchScene generatedScene(uint32_t subdivisions) {
    BenchScene b;
    b.scene.materials.push_back(scene::Material{});
    b.scene.meshes.push_back(icosphere(subdivisions));
    b.name = "icosphere" + std::to_string(b.scene.triangleCount() / 1000) + "k";
    b.scene.camera.position = {0.9f, 0.6f, 3.2f};
    b.scene.camera.target = {0.0f, 0.0f, 0.0f};
    b.scene.camera.xfovDegrees = 45.0f;
    b.camera = scene::makeGpuCamera(b.scene.camera, FILM, FILM);
    return b;
}

BenchScene loadedScene(const std::filesystem::path& path) {
    BenchScene b;
    b.name = path.stem().string();
    b.scene = scene::loadScene(path);
    b.camera = scene::makeGpuCamera(b.scene.camera, FILM, FILM);
    return b;
}

// ---- rays ----------------------------------------------------------------------

std::vector<shared::Ray> cameraRays(const shared::Camera& camera) {
    std::vector<shared::Ray> rays;
    rays.reserve(FILM * FILM);
    for (uint32_t y = 0; y < FILM; ++y)
        for (uint32_t x = 0; x < FILM; ++x)
            rays.push_back(shared::generateCameraRay(camera, glm::uvec2(x, y), glm::vec2(0.5f)));
    return rays;
}

// From every camera-ray hit, one ray in a uniformly random direction of the
// hemisphere it came from (a diffuse bounce): incoherent secondary rays.
std::vector<shared::Ray> bounceRays(const bvh::BvhBuild& build,
                                    const std::vector<shared::Ray>& primary) {
    const shared::BvhView view{build.traversalNodes, build.primitives};
    std::mt19937 rng(1);
    std::normal_distribution<float> n(0.0f, 1.0f);
    std::vector<shared::Ray> rays;
    for (const shared::Ray& r : primary) {
        const shared::Hit hit = view.bvhClosestHit(r);
        if (hit.primitive == VKP_NO_HIT) continue;
        const shared::SurfacePoint sp =
            shared::surfacePoint(build.primitives[hit.primitive], r, hit);
        const vec3 back = glm::dot(sp.normal, r.direction) < 0.0f ? sp.normal : -sp.normal;
        vec3 d = glm::normalize(vec3(n(rng), n(rng), n(rng)));
        if (glm::dot(d, back) < 0.0f) d = -d;
        rays.push_back(shared::spawnRay(sp, d, FLT_MAX_VALUE, r.pixel));
    }
    return rays;
}

// CPU seconds used by the whole process (all threads, lavapipe's workers
// included): on a loaded machine, rays per CPU second vary less than rays per
// wall-clock second.
double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](const timeval& t) {
        return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// ---- state shared by the benchmarks ------------------------------------------------

vk::Context& context() {
    static vk::Context c;
    return c;
}

std::vector<BenchScene>& scenes() {
    static std::vector<BenchScene> s;
    return s;
}

// ---- benchmarks -------------------------------------------------------------------

void buildBenchmark(benchmark::State& state, const scene::Scene* s, bvh::BvhOptions options) {
    bvh::BvhBuild build;
    for (auto _ : state) {
        build = bvh::buildBvh(*s, options);
        benchmark::DoNotOptimize(build.nodes.data());
    }
    const double primitives = static_cast<double>(build.primitives.size());
    state.counters["prims"] = primitives;
    state.counters["Mprims/s"] =
        benchmark::Counter(primitives * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["sah"] = build.stats.sahCost;
    state.counters["nodes"] = static_cast<double>(build.stats.nodes);
    state.counters["depth"] = build.stats.maxDepth;
    state.counters["MiB"] = static_cast<double>(build.bytes()) / (1024.0 * 1024.0);
}

enum class RayKind { Coherent, Incoherent };

void traceBenchmark(benchmark::State& state, const BenchScene* s, bvh::BvhOptions options,
                    RayKind kind, bool anyHit, uint32_t workgroupSize, bool byAddress) {
    const bvh::BvhBuild build = bvh::buildBvh(s->scene, options);
    std::vector<shared::Ray> rays = cameraRays(s->camera);
    if (kind == RayKind::Incoherent) rays = bounceRays(build, rays);
    if (rays.empty()) {
        state.SkipWithError("no rays");
        return;
    }
    vk::Context& c = context();
    const bvh::GpuBvh gpu = bvh::uploadBvh(c, build, byAddress);
    vk::Buffer rayBuffer = vk::Buffer::fromSpan(c, std::span(rays));
    vk::Buffer results(c, rays.size() * sizeof(shared::Hit));
    vk::Kernel kernel(c, anyHit ? "bvh_anyhit" : "bvh_closest",
                      vk::KernelOptions{.workgroupSize = workgroupSize,
                                        .specialization = {bvh::sceneAccessConstant(byAddress)}});
    const auto count = static_cast<uint32_t>(rays.size());
    const shared::TracePush push{count, gpu.addresses()};
    double totalMs = 0, cpuSeconds = 0;
    for (auto _ : state) {
        const double cpuBefore = processCpuSeconds();
        const double ms = kernel.dispatch(count,
                                          {{VKP_TRACE_BINDING_NODES, &gpu.nodeBinding()},
                                           {VKP_TRACE_BINDING_PRIMITIVES, &gpu.primitiveBinding()},
                                           {VKP_TRACE_BINDING_RAYS, &rayBuffer},
                                           {VKP_TRACE_BINDING_RESULTS, &results}},
                                          push);
        cpuSeconds += processCpuSeconds() - cpuBefore;
        state.SetIterationTime(ms * 1e-3);
        totalMs += ms;
    }
    state.counters["rays"] = count;
    state.counters["Mrays/s"] = static_cast<double>(count) *
                                static_cast<double>(state.iterations()) / (totalMs * 1e-3) * 1e-6;
    state.counters["Mrays/cpu-s"] =
        static_cast<double>(count) * static_cast<double>(state.iterations()) / cpuSeconds * 1e-6;
    state.counters["sah"] = build.stats.sahCost;
}

// The traversals on the CPU, one thread: the kernels' binary one
// (shared/bvh_traverse.h through BvhView), a yardstick for the GPU figures,
// and the eight-wide tree the CPU reference traces (bvh/wide_bvh.h).
void cpuTraceBenchmark(benchmark::State& state, const BenchScene* s, RayKind kind, bool wide) {
    const bvh::BvhBuild build = bvh::buildBvh(s->scene);
    std::vector<shared::Ray> rays = cameraRays(s->camera);
    if (kind == RayKind::Incoherent) rays = bounceRays(build, rays);
    const shared::BvhView view{build.traversalNodes, build.primitives};
    const bvh::WideBvh wideBvh = bvh::collapseBvh(build);
    for (auto _ : state)
        for (const shared::Ray& r : rays)
            benchmark::DoNotOptimize(wide ? bvh::traceWide(view, wideBvh, r, false, 0u)
                                          : view.bvhClosestHit(r));
    state.counters["rays"] = static_cast<double>(rays.size());
    state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(rays.size()) * 1e-6,
                                                   benchmark::Counter::kIsIterationInvariantRate);
    // What the tree takes beside the binary one's arrays (which shading reads too).
    if (wide) state.counters["wide MiB"] = static_cast<double>(wideBvh.bytes()) / (1024.0 * 1024.0);
}

void registerAll(const std::vector<std::filesystem::path>& scenePaths) {
    for (uint32_t subdivisions : {5u, 6u, 7u, 8u}) scenes().push_back(generatedScene(subdivisions));
    for (const auto& path : scenePaths) scenes().push_back(loadedScene(path));

    for (const BenchScene& s : scenes()) {
        const size_t triangles = s.scene.triangleCount();
        for (uint32_t threads : {1u, 0u}) {
            const std::string name = "build/" + s.name + (threads == 1 ? "/serial" : "/parallel");
            benchmark::RegisterBenchmark(name.c_str(), buildBenchmark, &s.scene,
                                         bvh::BvhOptions{.threads = threads})
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->Iterations(triangles > 500000 ? 2 : 5);
        }
        // The settings of the build times published with the Scotty3D
        // assignment (12 SAH buckets, leaves of at most 4, every thread).
        const std::string assignment = "build/" + s.name + "/bins:12/leaf:4";
        benchmark::RegisterBenchmark(assignment.c_str(), buildBenchmark, &s.scene,
                                     bvh::BvhOptions{.maxLeafSize = 4, .binCount = 12})
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(triangles > 500000 ? 2 : 5);
        for (uint32_t leaf : {1u, 2u, 4u, 8u, 15u}) {
            const std::string name = "build/" + s.name + "/leaf:" + std::to_string(leaf);
            benchmark::RegisterBenchmark(name.c_str(), buildBenchmark, &s.scene,
                                         bvh::BvhOptions{.maxLeafSize = leaf})
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->Iterations(triangles > 500000 ? 1 : 3);
        }
    }
    for (const BenchScene& s : scenes()) {
        if (s.scene.triangleCount() > 500000)
            continue;  // traversal: the smaller scenes are enough on lavapipe
        for (RayKind kind : {RayKind::Coherent, RayKind::Incoherent}) {
            for (bool wide : {false, true}) {
                const std::string cpuName =
                    "trace-cpu/" + s.name +
                    (kind == RayKind::Coherent ? "/coherent" : "/incoherent") + "/closest" +
                    (wide ? "/wide" : "/binary");
                // Half a second of passes over the rays: two passes (tens of
                // milliseconds) spread too much between runs of one binary on a
                // shared VM (docs/BENCHMARKS.md, "On the CPU (the eight-wide tree)").
                benchmark::RegisterBenchmark(cpuName.c_str(), cpuTraceBenchmark, &s, kind, wide)
                    ->Unit(benchmark::kMillisecond)
                    ->MinTime(0.5);
            }
            const std::string group =
                s.name + (kind == RayKind::Coherent ? "/coherent" : "/incoherent");
            for (bool anyHit : {false, true}) {
                const std::string hit = anyHit ? "/anyhit" : "/closest";
                // Scene arrays bound as storage buffers, or read by address
                // (the path for scenes beyond maxStorageBufferRange).
                for (bool byAddress : {false, true}) {
                    const std::string name =
                        "trace-access/" + group + hit + (byAddress ? "/address" : "/binding");
                    benchmark::RegisterBenchmark(name.c_str(), traceBenchmark, &s,
                                                 bvh::BvhOptions{}, kind, anyHit, DEFAULT_WORKGROUP,
                                                 byAddress)
                        ->Unit(benchmark::kMillisecond)
                        ->UseManualTime()
                        ->Iterations(5);
                }
                // Workgroup sizes (threads per workgroup of the trace kernels).
                for (uint32_t workgroup : {32u, 64u, 128u, 256u}) {
                    const std::string name =
                        "trace-wg/" + group + hit + "/wg:" + std::to_string(workgroup);
                    benchmark::RegisterBenchmark(name.c_str(), traceBenchmark, &s,
                                                 bvh::BvhOptions{}, kind, anyHit, workgroup, false)
                        ->Unit(benchmark::kMillisecond)
                        ->UseManualTime()
                        ->Iterations(5);
                }
            }
            for (bool anyHit : {false, true}) {
                // Leaf sizes at the default SAH traversal cost (1), then other
                // traversal costs with room for larger leaves.
                const std::pair<uint32_t, float> variants[] = {
                    {1, 1.0f}, {2, 1.0f}, {4, 1.0f}, {8, 1.0f}, {8, 0.5f}, {8, 2.0f}, {8, 4.0f}};
                for (const auto& [leaf, traversalCost] : variants) {
                    std::string name = "trace/" + s.name +
                                       (kind == RayKind::Coherent ? "/coherent" : "/incoherent") +
                                       (anyHit ? "/anyhit" : "/closest") +
                                       "/leaf:" + std::to_string(leaf);
                    if (traversalCost != 1.0f) name += "/ct:" + fmt::format("{}", traversalCost);
                    benchmark::RegisterBenchmark(
                        name.c_str(), traceBenchmark, &s,
                        bvh::BvhOptions{.maxLeafSize = leaf, .traversalCost = traversalCost}, kind,
                        anyHit, DEFAULT_WORKGROUP, false)
                        ->Unit(benchmark::kMillisecond)
                        ->UseManualTime()
                        ->Iterations(3);
                }
            }
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::filesystem::path> scenePaths;
    std::vector<char*> rest;
    bool scenesGiven = false;
    for (int i = 0; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind("--scene=", 0) == 0) {
            scenePaths.emplace_back(arg.substr(8));
            scenesGiven = true;
        } else {
            rest.push_back(argv[i]);
        }
    }
    if (!scenesGiven) {
        for (const char* name : {"bunny.dae", "CBbunny.dae", "plane16384.dae", "CBspheres.dae"}) {
            const std::filesystem::path p =
                std::filesystem::path(VKPATH_SCENES_DIR) / "scotty3d" / name;
            if (std::filesystem::exists(p)) scenePaths.push_back(p);
        }
    }
    int restCount = static_cast<int>(rest.size());
    benchmark::Initialize(&restCount, rest.data());
    try {
        vkpath::shaders::registerKernels(vkpath::shaders::testKernels());
        registerAll(scenePaths);
        std::fprintf(stderr, "bvh_bench: device %s\n", context().info().name.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bvh_bench: %s\n", e.what());
        return 1;
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
