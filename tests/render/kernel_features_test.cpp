// The feature bits a render's kernels are specialised to (shared/features.h,
// wavefront/kernel_features.h): exactly what the scene's tables and the
// settings contain, and what follows from them: no shadow stage and no
// shadow-ray memory where nothing can be light-sampled, and the megakernel's
// path state of 12 bytes a path.
#include "wavefront/kernel_features.h"

#include <gtest/gtest.h>

#include <cstring>

#include "bvh/bvh.h"
#include "scene/scene.h"
#include "shared/features.h"
#include "shared/microfacet_albedo.h"
#include "shared/ray.h"
#include "support/test_context.h"
#include "support/test_scenes.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

// One sphere of `kind` under a constant sky, as in the furnace tests.
scene::Scene sphereUnderSky(scene::MaterialKind kind) {
    return test::sphereInEnvironment(kind, glm::vec3(0.5f));
}

uint64_t featuresOf(const scene::Scene& s, const wavefront::RenderSettings& settings) {
    const wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    return wavefront::renderFeatures(tables, wavefront::renderSceneInfo(tables, settings));
}

TEST(KernelFeatures, ExactlyWhatTheSceneAndSettingsHold) {
    wavefront::RenderSettings settings;  // Sobol', one light sample, roulette from 5 at -m 8
    EXPECT_EQ(
        featuresOf(sphereUnderSky(scene::MaterialKind::Diffuse), settings),
        uint64_t(VKP_FEATURE_SPHERES | VKP_FEATURE_DIFFUSE | VKP_FEATURE_ENVIRONMENT_COLOR |
                 VKP_FEATURE_SAMPLER_SOBOL | VKP_FEATURE_LIGHT_SAMPLES | VKP_FEATURE_ROULETTE));

    settings.sampler = wavefront::SamplerKind::Independent;
    settings.lightSamples = 3;
    settings.rouletteDepth = settings.maxDepth + 1;  // roulette can never apply
    EXPECT_EQ(featuresOf(sphereUnderSky(scene::MaterialKind::Dielectric), settings),
              uint64_t(VKP_FEATURE_SPHERES | VKP_FEATURE_DIELECTRIC |
                       VKP_FEATURE_ENVIRONMENT_COLOR | VKP_FEATURE_SAMPLER_INDEPENDENT |
                       VKP_FEATURE_LIGHT_SAMPLES | VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES));

    // No light at all: no light samples, whatever -l says.
    scene::Scene dark = sphereUnderSky(scene::MaterialKind::Mirror);
    dark.environment.reset();
    EXPECT_EQ(featuresOf(dark, settings) &
                  (VKP_FEATURE_LIGHT_SAMPLES | VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES |
                   VKP_FEATURES_ENVIRONMENT),
              0u);
}

// Multiple-scattering compensation costs a scene without a rough GGX lobe
// nothing: no albedo tables, no feature bit (a smooth conductor, roughness 0,
// is the mirror-like delta); a rough one gets both unless --single-scattering,
// and path regularisation does not bring them to a mirror (compensation
// follows the material's own roughness: shared/integrator.h shadeHit).
TEST(KernelFeatures, MicrofacetCompensationOnlyWithARoughLobe) {
    wavefront::RenderSettings settings;
    scene::Scene smooth = sphereUnderSky(scene::MaterialKind::Conductor);
    smooth.materials[0].roughness = 0.0f;
    EXPECT_TRUE(wavefront::buildSceneTables(smooth).microfacetAlbedo.empty());
    EXPECT_EQ(featuresOf(smooth, settings) & VKP_FEATURE_MICROFACET_COMPENSATION, 0u);
    scene::Scene rough = smooth;
    rough.materials[0].roughness = 0.5f;
    EXPECT_EQ(wavefront::buildSceneTables(rough).microfacetAlbedo.size(), VKP_ALBEDO_TABLE_SIZE);
    EXPECT_NE(featuresOf(rough, settings) & VKP_FEATURE_MICROFACET_COMPENSATION, 0u);
    settings.microfacetCompensation = false;
    EXPECT_EQ(featuresOf(rough, settings) & VKP_FEATURE_MICROFACET_COMPENSATION, 0u);
    settings.microfacetCompensation = true;
    settings.regularize = 0.1f;
    EXPECT_EQ(featuresOf(sphereUnderSky(scene::MaterialKind::Mirror), settings) &
                  VKP_FEATURE_MICROFACET_COMPENSATION,
              0u);
}

// The clear coat, the sheen and the thin wall are bits of their own, set
// only where a material has one; a sheen brings the albedo tables (its
// albedo scaling reads them) without compensation's bit when no GGX lobe is
// rough.
TEST(KernelFeatures, MaterialExtensionsOnlyWhereAMaterialHasThem) {
    const wavefront::RenderSettings settings;
    scene::Scene plain = sphereUnderSky(scene::MaterialKind::MetallicRoughness);
    plain.materials[0].roughness = 0.0f;
    const uint64_t layers = VKP_FEATURE_CLEARCOAT | VKP_FEATURE_SHEEN;
    EXPECT_EQ(featuresOf(plain, settings) & layers, 0u);
    EXPECT_TRUE(wavefront::buildSceneTables(plain).microfacetAlbedo.empty());
    scene::Scene coated = plain;
    coated.materials[0].clearcoat = 0.5f;
    EXPECT_EQ(featuresOf(coated, settings) & layers, VKP_FEATURE_CLEARCOAT);
    scene::Scene sheened = plain;
    sheened.materials[0].sheenColor = {0.0f, 0.2f, 0.0f};
    EXPECT_EQ(featuresOf(sheened, settings) & layers, VKP_FEATURE_SHEEN);
    EXPECT_EQ(wavefront::buildSceneTables(sheened).microfacetAlbedo.size(), VKP_ALBEDO_TABLE_SIZE);
    EXPECT_EQ(featuresOf(sheened, settings) & VKP_FEATURE_MICROFACET_COMPENSATION, 0u);
    scene::Scene glass = sphereUnderSky(scene::MaterialKind::Dielectric);
    EXPECT_EQ(featuresOf(glass, settings) & VKP_FEATURE_THIN_WALLED, 0u);
    glass.materials[0].thinWalled = true;
    EXPECT_NE(featuresOf(glass, settings) & VKP_FEATURE_THIN_WALLED, 0u);
    EXPECT_EQ(featuresOf(plain, settings) & VKP_FEATURE_DIFFUSE_TRANSMISSION, 0u);
    scene::Scene leaf = plain;
    leaf.materials[0].diffuseTransmission = 0.3f;
    EXPECT_NE(featuresOf(leaf, settings) & VKP_FEATURE_DIFFUSE_TRANSMISSION, 0u);
    EXPECT_EQ(featuresOf(leaf, settings) & VKP_FEATURE_IRIDESCENCE, 0u);
    leaf.materials[0].iridescence = 0.5f;
    EXPECT_NE(featuresOf(leaf, settings) & VKP_FEATURE_IRIDESCENCE, 0u);
    EXPECT_EQ(featuresOf(leaf, settings) & VKP_FEATURE_ANISOTROPY, 0u);
    leaf.materials[0].anisotropy = 0.5f;
    EXPECT_NE(featuresOf(leaf, settings) & VKP_FEATURE_ANISOTROPY, 0u);
    // Dispersion on solid glass only: a thin wall bends no light.
    scene::Scene prism = plain;
    prism.materials[0].kind = scene::MaterialKind::Dielectric;
    prism.materials[0].dispersion = 0.5f;
    EXPECT_NE(featuresOf(prism, settings) & VKP_FEATURE_DISPERSION, 0u);
    prism.materials[0].thinWalled = true;
    EXPECT_EQ(featuresOf(prism, settings) & VKP_FEATURE_DISPERSION, 0u);
}

TEST(KernelFeatures, NamesTheBitsAndTheGeneralKernel) {
    EXPECT_EQ(wavefront::describeFeatures(VKP_FEATURE_TRIANGLES | VKP_FEATURE_DIFFUSE |
                                          VKP_FEATURE_ROULETTE),
              "triangles diffuse roulette");
    EXPECT_EQ(wavefront::describeFeatures(VKP_FEATURES_ALL), "general");
}

TEST(KernelFeatures, NoShadowStageOrMemoryWhereNothingCanBeLightSampled) {
    wavefront::RenderSettings settings;
    settings.width = 16;
    settings.height = 12;
    settings.samplesPerPixel = 1;
    settings.kernel = wavefront::KernelForm::Wavefront;
    auto pathState = [&](const scene::Scene& s, bool specialize) {
        settings.specialize = specialize;
        wavefront::GpuRenderer renderer(test::context(), s, settings);
        EXPECT_EQ(renderer.memory().at(1).name, "path state");
        return renderer.memory().at(1).bytes / renderer.pathsInFlight();
    };
    // A mirror under the sky: a light to sample but no surface to sample it
    // from. Specialised, the shadow rays and their contributions (32 + 12
    // bytes a path) are not allocated; the general kernels keep them, and the
    // wavelength of dispersion (4 bytes), which no specialised kernel of a
    // scene without dispersive glass keeps.
    const scene::Scene mirror = sphereUnderSky(scene::MaterialKind::Mirror);
    EXPECT_EQ(pathState(mirror, true),
              wavefront::pathStateBytes(wavefront::KernelForm::Wavefront, 0));
    EXPECT_EQ(pathState(mirror, false), wavefront::pathStateBytes(wavefront::KernelForm::Wavefront,
                                                                  1, {.wavelengths = true}));
    EXPECT_EQ(
        wavefront::pathStateBytes(wavefront::KernelForm::Wavefront, 0, {.wavelengths = true}) -
            wavefront::pathStateBytes(wavefront::KernelForm::Wavefront, 0),
        sizeof(float));
    EXPECT_EQ(wavefront::pathStateBytes(wavefront::KernelForm::Wavefront, 1) -
                  wavefront::pathStateBytes(wavefront::KernelForm::Wavefront, 0),
              sizeof(shared::Ray) + sizeof(glm::vec3));
    // The megakernel keeps only each path's radiance.
    EXPECT_EQ(wavefront::pathStateBytes(wavefront::KernelForm::Megakernel, 1), sizeof(glm::vec3));
}

}  // namespace

namespace {

// A floor of n x n quads (2 n^2 triangles) under a white sky, seen from above.
scene::Scene floorOfQuads(uint32_t n) {
    scene::Scene s = sphereUnderSky(scene::MaterialKind::Mirror);
    scene::Mesh floor;
    floor.name = "floor";
    for (uint32_t y = 0; y <= n; ++y)
        for (uint32_t x = 0; x <= n; ++x)
            floor.positions.emplace_back(4.0f * float(x) / float(n) - 2.0f, -1.0f,
                                         4.0f * float(y) / float(n) - 2.0f);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
            floor.triangles.emplace_back(a, c, b);
            floor.triangles.emplace_back(b, c, d);
        }
    scene::Material grey;
    grey.reflectance = glm::vec3(0.5f);
    s.materials.push_back(grey);
    floor.material = 1;
    s.meshes.push_back(floor);
    s.camera.position = {0.0f, 3.0f, 3.0f};
    return s;
}

}  // namespace

// A scene too large for its BVH to be shallow has its pipelines compiled
// while the BVH builds (the tables before it foretell them), and renders the
// image of a renderer made from finished tables, bit for bit; a scene whose
// BVH might be shallow waits for it.
TEST(KernelFeatures, ALargeScenesPipelinesCompileWhileItsBvhBuilds) {
    wavefront::RenderSettings settings;
    settings.width = 24;
    settings.height = 16;
    settings.samplesPerPixel = 2;
    for (const wavefront::KernelForm form :
         {wavefront::KernelForm::Megakernel, wavefront::KernelForm::Wavefront}) {
        settings.kernel = form;
        const scene::Scene large = floorOfQuads(32);  // 2048 triangles, more than 4 << 8
        wavefront::GpuRenderer prewarmed(test::context(), large, settings);
        EXPECT_TRUE(prewarmed.pipelinesPrewarmed());
        EXPECT_NE(prewarmed.describe().find("compiled while the BVH was built"), std::string::npos);
        wavefront::GpuRenderer fromTables(test::context(), wavefront::buildSceneTables(large),
                                          settings);
        EXPECT_FALSE(fromTables.pipelinesPrewarmed());
        const auto a = prewarmed.render(), b = fromTables.render();
        ASSERT_EQ(a.image.pixels.size(), b.image.pixels.size());
        EXPECT_EQ(0, std::memcmp(a.image.pixels.data(), b.image.pixels.data(),
                                 a.image.pixels.size() * sizeof(glm::vec3)));
    }
    // 128 triangles may make a shallow tree: its features wait for the BVH.
    EXPECT_FALSE(bvh::predictedTraversalFeatures(floorOfQuads(8)).has_value());
}
