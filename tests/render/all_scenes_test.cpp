// Every scene the project ships or reads (<scenes>/scotty3d/*.dae and
// assets/*.gltf, its repeated meshes instanced) renders through the
// wavefront path tracer at low spp with
// no NaN or infinite sample and a finite, non-negative image, and its BVH
// passes the integrity check. On every one, the GPU's four kernel builds
// (wavefront or megakernel, specialised or general) give the same image bit
// for bit, and so do the CPU reference's builds (a profile and the general
// code).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include "bvh/bvh.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "support/test_context.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

// The assignment's scenes only where they are (AllScenes.IncludeTheAssignmentsScenes
// says when not).
std::vector<std::string> sceneFiles() {
    std::vector<std::string> files;
    std::vector<std::filesystem::path> folders = {test::sourcePath("assets")};
    if (test::sharedScenesMissing().empty()) folders.push_back(test::sharedScene(""));
    for (const auto& dir : folders)
        for (const auto& entry : std::filesystem::directory_iterator(dir)) {
            const auto ext = entry.path().extension();
            if (ext == ".dae" || ext == ".gltf" || ext == ".glb")
                files.push_back(entry.path().string());
        }
    std::sort(files.begin(), files.end());
    return files;
}

class AllScenes : public testing::TestWithParam<std::string> {};

// Every mesh that several nodes place is instanced (--instancing on), so that
// instancing (assets/instances.gltf) meets every kernel and check here.
scene::Scene loadInstanced(const std::string& path) {
    scene::LoadOptions options;
    options.instancing = scene::Instancing::On;
    return scene::loadScene(path, options);
}

TEST_P(AllScenes, RenderWithoutNonFiniteSamples) {
    const scene::Scene s = loadInstanced(GetParam());
    // The renderer's builder and options: every primitive in exactly one leaf,
    // every child box inside its parent.
    EXPECT_EQ(bvh::integrityCheck(bvh::buildBvh(s), s), std::vector<std::string>{});
    wavefront::RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.samplesPerPixel = 2;
    settings.maxDepth = 4;
    settings.lightSamples = 2;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    const auto r = renderer.render();
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    double sum = 0;
    for (const glm::vec3& p : r.image.pixels)
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(p[c]));
            ASSERT_GE(p[c], 0.0f);
            sum += p[c];
        }
    EXPECT_GT(sum, 0.0) << "the image is black";
}

// The renderer compiles a large scene's pipelines while its BVH builds,
// for the features the tables before the BVH foretell: on every scene those
// (with the BVH's traversal bits) are the tables' own, and where the BVH's
// size foretells its traversal bits they are the BVH's. (One test over all
// the files: a process each would cost more than the checks.)
TEST(AllSceneFiles, TheTablesBeforeTheBvhForetellTheFeatures) {
    for (const std::string& file : sceneFiles()) {
        SCOPED_TRACE(file);
        const scene::Scene s = loadInstanced(file);
        std::optional<wavefront::SceneTables> before;
        const wavefront::SceneTables tables = wavefront::buildSceneTables(
            s, {}, [&](const wavefront::SceneTables& t) { before = t; });
        ASSERT_TRUE(before.has_value());
        EXPECT_TRUE(before->bvh.primitives.empty());
        const wavefront::RenderSettings settings;
        const uint64_t traversal = bvh::traversalFeatures(tables.bvh);
        EXPECT_EQ(
            wavefront::renderFeatures(*before, wavefront::renderSceneInfo(*before, settings)) |
                traversal,
            wavefront::renderFeatures(tables, wavefront::renderSceneInfo(tables, settings)));
        if (const auto predicted = bvh::predictedTraversalFeatures(s)) {
            EXPECT_EQ(*predicted, traversal);
        }
    }
}

// The microfacet kinds (rough conductor, rough glass, metallic-roughness)
// came after these scenes. The COLLADA scenes keep their kinds (no material
// of theirs has a rough glass). The bundled glTF scenes keep theirs too,
// with one exception: a glTF metal is the conductor of Schlick's Fresnel
// (glTF 2.0 Appendix B), so their mirror spheres (metallic 1, roughness 0)
// are smooth conductors, whose reflectance rises from F0 = 0.95 toward 1 at
// grazing angles. Their diffuse materials say KHR_materials_specular
// specularFactor 0, which is exactly Lambertian. Scenes made with the
// microfacet kinds (the roughness sweep; the instanced tori, of gold and red
// plastic; the coats and sheens over metallic-roughness) are listed here.
TEST_P(AllScenes, KeepTheirMaterialKinds) {
    const std::string name = std::filesystem::path(GetParam()).filename().string();
    const std::vector<std::string> showingMicrofacets = {"material_spheres.gltf", "instances.gltf",
                                                         "material_extensions.gltf"};
    if (std::find(showingMicrofacets.begin(), showingMicrofacets.end(), name) !=
        showingMicrofacets.end())
        GTEST_SKIP() << name << " is made to show the microfacet kinds";
    const scene::Scene s = loadInstanced(GetParam());
    for (const scene::Material& m : s.materials) {
        const bool smoothConductor =
            m.kind == scene::MaterialKind::Conductor && m.roughness == 0.0f;
        const bool microfacet = m.kind == scene::MaterialKind::Conductor ||
                                m.kind == scene::MaterialKind::RoughDielectric ||
                                m.kind == scene::MaterialKind::MetallicRoughness;
        EXPECT_TRUE(!microfacet || smoothConductor) << m.name;
    }
}

bool sameBits(const image::Image& a, const image::Image& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

// Pixels of `a` whose largest relative difference from `b` exceeds `relative`.
size_t pixelsApart(const image::Image& a, const image::Image& b, double relative) {
    size_t apart = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double x = a.pixels[i][c], y = b.pixels[i][c];
            if (std::abs(x - y) > relative * std::max({std::abs(x), std::abs(y), 1e-6})) {
                ++apart;
                break;
            }
        }
    return apart;
}

// The same image and variance bit for bit, and the same counts, on a CPU
// Vulkan device (lavapipe rounds every operation as the SPIR-V writes it).
//
// A GPU's compiler may choose, kernel by kernel, how to evaluate a division
// or a square root (Vulkan allows them ulps of error) or an extended
// instruction such as normalize; the host forbids fused multiply-adds
// (vk/spirv_no_contraction.h), which made 27 of the 28 scenes bit for bit
// alike on an H200. normal_maps (a tangent frame normalised at every hit)
// still differs there: at 400x300 and 16 spp, 93.5% of pixels identical, the
// rest mostly by one ulp, 0.14% by more than 1e-5 relative, 0.017% by more
// than 1e-3 (a path that took the other branch: 3 of 3.4 million closest-hit
// rays differed). On such a device: at most 1% of pixels more than 1e-5
// apart (7 times the measured share), and counts within 1e-4 relative (about
// 100 times the measured).
void expectSameRender(const wavefront::RenderResult& r, const wavefront::RenderResult& expected) {
    if (test::context().info().type == "cpu") {
        EXPECT_TRUE(sameBits(r.image, expected.image));
        EXPECT_TRUE(sameBits(r.varianceOfMean, expected.varianceOfMean));
        EXPECT_EQ(r.rays.closest, expected.rays.closest);
        EXPECT_EQ(r.rays.shadow, expected.rays.shadow);
        EXPECT_EQ(r.rejectedLightSamples, expected.rejectedLightSamples);
        EXPECT_EQ(r.fireflySamples, expected.fireflySamples);
        return;
    }
    EXPECT_LE(pixelsApart(r.image, expected.image, 1e-5), r.image.pixels.size() / 100);
    auto near = [](uint64_t a, uint64_t b) {
        return std::abs(double(a) - double(b)) <= 1e-4 * double(b) + 2.0;
    };
    EXPECT_PRED2(near, r.rays.closest, expected.rays.closest);
    EXPECT_PRED2(near, r.rays.shadow, expected.rays.shadow);
    EXPECT_PRED2(near, r.rejectedLightSamples, expected.rejectedLightSamples);
    EXPECT_PRED2(near, r.fireflySamples, expected.fireflySamples);
}

// The two settings the same-image tests render with: the defaults (one light
// sample, the Sobol' sampler, roulette from bounce 5 of 5), and their
// opposites (three light samples, the independent sampler, no roulette, path
// regularisation), so that every feature bit of the settings is both on and
// off somewhere.
wavefront::RenderSettings sameImageSettings(bool defaults) {
    wavefront::RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
    settings.samplesPerPixel = 2;
    settings.maxDepth = 5;
    if (!defaults) {
        settings.lightSamples = 3;
        settings.sampler = wavefront::SamplerKind::Independent;
        settings.rouletteDepth = 6;
        settings.regularize = 0.2f;
    }
    return settings;
}

// Specialisation removes only code that the scene's data never takes, and
// the megakernel runs the wavefront stages' functions in the same order
// (shared/integrator.h): with the same seed, the same bits, in both of
// sameImageSettings.
TEST_P(AllScenes, EveryKernelGivesTheSameImage) {
    const scene::Scene s = loadInstanced(GetParam());
    for (const bool defaults : {true, false}) {
        SCOPED_TRACE(defaults ? "default settings"
                              : "3 light samples, independent, no roulette, regularised");
        wavefront::RenderSettings settings = sameImageSettings(defaults);
        settings.kernel = wavefront::KernelForm::Wavefront;
        wavefront::GpuRenderer reference(test::context(), s, settings);
        const auto expected = reference.render();
        EXPECT_NE(reference.features(), VKP_FEATURES_ALL);
        for (const auto form :
             {wavefront::KernelForm::Wavefront, wavefront::KernelForm::Megakernel})
            for (const bool specialize : {true, false}) {
                if (form == wavefront::KernelForm::Wavefront && specialize) continue;
                SCOPED_TRACE(fmt::format("{} {}", wavefront::kernelFormName(form),
                                         specialize ? "specialised" : "general"));
                settings.kernel = form;
                settings.specialize = specialize;
                wavefront::GpuRenderer renderer(test::context(), s, settings);
                EXPECT_EQ(renderer.features(),
                          specialize ? reference.features() : VKP_FEATURES_ALL);
                expectSameRender(renderer.render(), expected);
            }
    }
}

// The CPU reference compiled for a profile (shared/feature_profiles.h) leaves
// out only code that the scene's data never takes: the image of its general
// build, bit for bit, in both of sameImageSettings. A scene whose features a
// profile holds runs the first such profile.
TEST_P(AllScenes, TheCpuProfileGivesTheSameImage) {
    const scene::Scene s = loadInstanced(GetParam());
    for (const bool defaults : {true, false}) {
        SCOPED_TRACE(defaults ? "default settings"
                              : "3 light samples, independent, no roulette, regularised");
        wavefront::RenderSettings settings = sameImageSettings(defaults);
        settings.specialize = false;
        const reference::ReferenceRenderer general(s, settings);
        EXPECT_EQ(general.sampler().features(), VKP_FEATURES_ALL);
        settings.specialize = true;
        const reference::ReferenceRenderer specialised(s, settings);
        const uint64_t features = specialised.features();
        const auto profiles = reference::cpuProfiles();
        const auto holding = std::find_if(
            profiles.begin(), profiles.end(),
            [&](const reference::CpuProfile& p) { return (features & ~p.features) == 0; });
        EXPECT_EQ(specialised.sampler().features(),
                  holding == profiles.end() ? VKP_FEATURES_ALL : holding->features);
        SCOPED_TRACE(specialised.describe());

        expectSameRender(specialised.render(), general.render());
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, AllScenes, testing::ValuesIn(sceneFiles()),
                         [](const testing::TestParamInfo<std::string>& param) {
                             std::string name = std::filesystem::path(param.param).stem().string();
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

// Where the assignment's scene folder is absent, AllScenes covers assets/
// only: this test skips, saying which scenes are left out.
TEST(AllScenesList, IncludeTheAssignmentsScenes) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const std::vector<std::string> files = sceneFiles();
    EXPECT_TRUE(std::any_of(files.begin(), files.end(),
                            [](const std::string& f) { return f.ends_with(".dae"); }));
}

}  // namespace
