// The registry of material kinds (shaders/shared/material_kinds.h) walked
// row by row: its numbers, names and feature bits are what the kernels and
// the host read; every kind samples, evaluates and gives the density of its
// samples consistently through shared/bsdf.h's dispatch (the shared code
// compiled as C++, as the CPU reference runs it); its flags say what its
// functions do; path regularisation turns it into the kind its row names; an
// importer makes it from a file (or the test states why none does); and the
// Mitsuba export writes a BSDF for it. The lobes' own statistics are
// microfacet_test.cpp's and material_bsdf_test.cpp's.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <pugixml.hpp>
#include <random>
#include <set>
#include <string>

#include "scene/load.h"
#include "scene/mitsuba_export.h"
#include "scene/scene.h"
#include "shared/bsdf.h"
#include "support/temp_dir.h"
#include "support/test_context.h"
#include "support/test_scenes.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"

namespace {

using namespace vkpath;
using test::gpuMaterial;
using test::sphereTables;

// A material of each kind with lobes that are not delta (where the kind has
// such lobes). No default: a new kind fails to compile until it has one.
scene::Material exampleMaterial(scene::MaterialKind kind) {
    scene::Material m;
    m.kind = kind;
    m.reflectance = glm::vec3(0.7f, 0.5f, 0.3f);
    switch (kind) {
        case scene::MaterialKind::Diffuse:
        case scene::MaterialKind::Mirror:
        case scene::MaterialKind::Dielectric:
            break;
        case scene::MaterialKind::Conductor:
            m.roughness = 0.5f;
            break;
        case scene::MaterialKind::RoughDielectric:
            m.roughness = 0.5f;
            break;
        case scene::MaterialKind::MetallicRoughness:
            m.roughness = 0.5f;
            m.metallic = 0.3f;
            break;
    }
    return m;
}

// A file an importer makes a material of `kind` from, relative to the
// repository (assets/) or to the assignment's scenes (scotty3d/); empty
// where no importer makes the kind, with the reason in `why`.
std::string importedFrom(scene::MaterialKind kind, std::string& why) {
    switch (kind) {
        case scene::MaterialKind::Diffuse:
            return "assets/cornell_box_diffuse.gltf";
        case scene::MaterialKind::Mirror:
            return "scotty3d/CBspheres.dae";
        case scene::MaterialKind::Dielectric:
            return "assets/cornell_box.gltf";
        case scene::MaterialKind::Conductor:
            return "assets/material_spheres.gltf";
        case scene::MaterialKind::RoughDielectric:
            return "assets/material_spheres.gltf";
        case scene::MaterialKind::MetallicRoughness:
            return "assets/material_spheres.gltf";
    }
    why = "no importer";
    return {};
}

TEST(MaterialRegistry, RowsAreNumberedInOrderWithUniqueNamesAndBits) {
    std::set<std::string> keys, labels;
    uint64_t features = 0;
    for (uint32_t i = 0; i < VKP_MATERIAL_KIND_COUNT; ++i) {
        const scene::MaterialKindInfo& row = scene::MATERIAL_KINDS[i];
        SCOPED_TRACE(row.label);
        EXPECT_EQ(uint32_t(row.kind), i);
        EXPECT_TRUE(keys.insert(row.key).second);
        EXPECT_TRUE(labels.insert(row.label).second);
        // One bit, of no other kind, named in the logs by the row's label.
        EXPECT_EQ(std::popcount(row.feature), 1);
        EXPECT_EQ(features & row.feature, 0u);
        features |= row.feature;
        EXPECT_EQ(wavefront::describeFeatures(row.feature), row.label);
        // The kernels' view of the row.
        EXPECT_EQ(shared::materialFeature(i), row.feature);
        EXPECT_EQ(shared::materialKindFlags(i), row.flags);
        EXPECT_EQ((VKP_FEATURES_NON_DELTA & row.feature) != 0,
                  (row.flags & VKP_KIND_NON_DELTA) != 0);
        EXPECT_EQ((VKP_FEATURES_MICROFACET & row.feature) != 0,
                  (row.flags & VKP_KIND_MICROFACET) != 0);
        EXPECT_EQ((VKP_FEATURES_TRANSMITS & row.feature) != 0,
                  (row.flags & VKP_KIND_TRANSMITS) != 0);
    }
    EXPECT_EQ(features, VKP_FEATURES_MATERIALS);
}

// Through the dispatch, on 4096 directions toward the surface from each
// side: a non-delta sample's weight is evalBsdf / bsdfPdf and its pdf is
// bsdfPdf's; a delta sample has no density for eval and pdf to see. The
// flags agree with what the functions do.
TEST(MaterialRegistry, EveryKindSamplesEvaluatesAndGivesItsDensity) {
    for (const scene::MaterialKindInfo& row : scene::MATERIAL_KINDS) {
        SCOPED_TRACE(row.label);
        const shared::Material m = gpuMaterial(exampleMaterial(row.kind));
        ASSERT_EQ(m.kind, uint32_t(row.kind));
        EXPECT_EQ(shared::hasNonDeltaLobe(m), (row.flags & VKP_KIND_NON_DELTA) != 0);
        EXPECT_EQ(shared::bsdfNeedsLobeChoice(m), (row.flags & VKP_KIND_LOBE_CHOICE) != 0);
        EXPECT_EQ(shared::materialTransmits(m), (row.flags & VKP_KIND_TRANSMITS) != 0);

        std::mt19937 rng(7);
        std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
        const glm::vec3 n(0.0f, 0.0f, 1.0f);
        int valid = 0, nonDelta = 0, transmitted = 0;
        for (int i = 0; i < 4096; ++i) {
            const float cosTheta = 0.05f + 0.9f * uniform(rng), phi = 6.2831853f * uniform(rng);
            const float sinTheta = std::sqrt(1.0f - cosTheta * cosTheta);
            glm::vec3 wo(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
            if (i % 2 == 1) wo.z = -wo.z;  // from the other side
            const shared::BsdfSample s = shared::sampleBsdf(
                m, n, n, wo, glm::vec2(uniform(rng), uniform(rng)), uniform(rng));
            if (!s.valid) continue;
            ++valid;
            EXPECT_NEAR(glm::length(s.direction), 1.0f, 1e-5f);
            if (s.direction.z * wo.z < 0.0f) ++transmitted;
            const glm::vec3 f = shared::evalBsdf(m, n, n, wo, s.direction);
            const float pdf = shared::bsdfPdf(m, n, n, wo, s.direction);
            if (s.delta) {
                EXPECT_EQ(pdf, 0.0f) << "a delta lobe sample has no density";
                continue;
            }
            ++nonDelta;
            ASSERT_GT(pdf, 0.0f);
            EXPECT_NEAR(s.pdf, pdf, 2e-3f * pdf);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(s.weight[c], f[c] / pdf, 2e-3f * (1.0f + s.weight[c]));
        }
        EXPECT_GT(valid, 2048);
        EXPECT_EQ(nonDelta > 0, (row.flags & VKP_KIND_NON_DELTA) != 0);
        EXPECT_EQ(transmitted > 0, (row.flags & VKP_KIND_TRANSMITS) != 0);
    }
}

// Every kind's albedo AOV (shared/bsdf.h materialAlbedo) is in [0, 1], and
// the example's (0.7, 0.5, 0.3) shows in it where the kind's albedo is its
// colour: every kind but the two dielectrics, whose albedo is 1.
TEST(MaterialRegistry, EveryKindHasAnAlbedoInTheUnitRange) {
    for (const scene::MaterialKindInfo& row : scene::MATERIAL_KINDS) {
        SCOPED_TRACE(row.label);
        const glm::vec3 albedo = shared::materialAlbedo(gpuMaterial(exampleMaterial(row.kind)));
        const bool dielectric = (row.flags & VKP_KIND_TRANSMITS) != 0;
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(albedo[c], 0.0f);
            EXPECT_LE(albedo[c], 1.0f);
        }
        EXPECT_EQ(albedo, dielectric ? glm::vec3(1.0f) : glm::vec3(0.7f, 0.5f, 0.3f));
    }
}

TEST(MaterialRegistry, RegularizationMakesTheKindItsRowNames) {
    for (const scene::MaterialKindInfo& row : scene::MATERIAL_KINDS) {
        SCOPED_TRACE(row.label);
        const shared::Material m = gpuMaterial(exampleMaterial(row.kind));
        const shared::Material r = shared::regularizedMaterial(m, 0.3f);
        EXPECT_EQ(r.kind, uint32_t(row.regularized));
        if (row.flags & VKP_KIND_MICROFACET) {
            EXPECT_GE(r.roughness, std::sqrt(0.3f) * (1.0f - 1e-6f));
        }
        // The renderer's kernels hold the kind a regularised render meets.
        const wavefront::SceneTables tables = sphereTables(exampleMaterial(row.kind));
        shared::SceneInfo info = tables.info;
        info.regularizeAlpha = 0.3f;
        const uint64_t features = wavefront::renderFeatures(tables, info);
        EXPECT_NE(features & scene::materialKindInfo(row.regularized).feature, 0u);
    }
}

TEST(MaterialRegistry, EveryKindIsImportedFromAFile) {
    for (const scene::MaterialKindInfo& row : scene::MATERIAL_KINDS) {
        SCOPED_TRACE(row.label);
        std::string why;
        const std::string file = importedFrom(row.kind, why);
        ASSERT_FALSE(file.empty()) << why;
        std::filesystem::path path;
        if (file.starts_with("scotty3d/")) {
            const std::filesystem::path shared = test::sharedScene(file.substr(9));
            if (!std::filesystem::exists(shared)) {
                std::printf("[  SKIPPED ] %s: %s is absent\n", row.label, shared.c_str());
                continue;
            }
            path = shared;
        } else {
            path = std::filesystem::path(VKPATH_SOURCE_DIR) / file;
        }
        const scene::Scene s = scene::loadScene(path);
        bool found = false;
        for (const scene::Material& m : s.materials) found |= m.kind == row.kind;
        EXPECT_TRUE(found) << path << " has no " << row.label << " material";
    }
}

TEST(MaterialRegistry, EveryKindIsExportedToMitsuba) {
    for (const scene::MaterialKindInfo& row : scene::MATERIAL_KINDS) {
        SCOPED_TRACE(row.label);
        scene::Scene s;
        s.materials.push_back(exampleMaterial(row.kind));
        s.spheres.push_back({"ball", glm::vec3(0.0f), 1.0f, 0});
        const test::TempDir dir;
        const scene::MitsubaExportResult result = scene::exportMitsuba(s, {}, dir.path());
        pugi::xml_document xml;
        ASSERT_TRUE(xml.load_file(result.xml.c_str()));
        const pugi::xml_node bsdf =
            xml.child("scene").find_child_by_attribute("bsdf", "id", "mat0");
        ASSERT_TRUE(bsdf) << "no BSDF for the " << row.label << " material";
        EXPECT_FALSE(std::string(bsdf.attribute("type").value()).empty());
    }
}

}  // namespace
