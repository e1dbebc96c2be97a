// `vkpath scene-info FILE [--json]`: what a scene file becomes after import:
// counts, materials by kind, emitters, lights, the framed camera, bounds and
// the feature summary the kernels are specialised to. Needs no Vulkan device.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/commands.h"
#include "scene/load.h"
#include "scene/scene.h"
#include "shared/wavefront.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"
#include "wavefront/renderer.h"
#include "wavefront/scene_footprint.h"

namespace vkpath::app {
namespace {

struct SceneCounts {
    size_t byKind[VKP_MATERIAL_KIND_COUNT] = {};  // materials by kind (scene::MATERIAL_KINDS order)
    size_t emissive = 0;
    size_t texels = 0;  // of all decoded images
    size_t emissiveMeshes = 0, emissiveSpheres = 0, emissiveTriangles = 0;
    bool hasBounds = false;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};  // meshes and spheres, world space
};

// What a render at the default settings would build for the scene: the
// feature set of its kernels and the device memory it takes, by group
// (the same functions as the renderer's; no device needed).
struct KernelPlan {
    uint64_t features = 0;
    uint64_t sceneBytes = 0;
    uint64_t wavefrontPathBytes = 0;  // per path in flight
    uint64_t megakernelPathBytes = 0;
};

KernelPlan planKernels(const scene::Scene& s) {
    const wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    const shared::SceneInfo info = wavefront::renderSceneInfo(tables, wavefront::RenderSettings{});
    KernelPlan plan;
    plan.features = wavefront::renderFeatures(tables, info);
    plan.sceneBytes = wavefront::deviceBytes(tables);
    const uint32_t shadowRays = wavefront::shadowRaysPerVertex(plan.features, info.lightSamples);
    const wavefront::PathExtras extras{.wavelengths =
                                           (plan.features & VKP_FEATURE_DISPERSION) != 0};
    plan.wavefrontPathBytes =
        wavefront::pathStateBytes(wavefront::KernelForm::Wavefront, shadowRays, extras);
    plan.megakernelPathBytes =
        wavefront::pathStateBytes(wavefront::KernelForm::Megakernel, shadowRays, extras);
    return plan;
}

SceneCounts countScene(const scene::Scene& s) {
    SceneCounts c;
    for (const scene::TextureImage& image : s.images) c.texels += image.texels.size();
    for (const scene::Material& m : s.materials) {
        ++c.byKind[uint32_t(m.kind)];
        c.emissive += m.emissive();
    }
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const scene::Mesh& mesh : s.meshes) {
        if (mesh.material < s.materials.size() && s.materials[mesh.material].emissive() &&
            !mesh.triangles.empty()) {
            ++c.emissiveMeshes;
            c.emissiveTriangles += mesh.triangles.size();
        }
        if (mesh.instanced) continue;
        for (const glm::vec3& p : mesh.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
            c.hasBounds = true;
        }
    }
    if (!s.instances.empty()) {
        const scene::Bounds placed = s.geometryBounds();
        lo = glm::min(lo, placed.lo);
        hi = glm::max(hi, placed.hi);
        c.hasBounds = true;
    }
    for (const scene::Sphere& sphere : s.spheres) {
        if (sphere.material < s.materials.size() && s.materials[sphere.material].emissive())
            ++c.emissiveSpheres;
        lo = glm::min(lo, sphere.center - sphere.radius);
        hi = glm::max(hi, sphere.center + sphere.radius);
        c.hasBounds = true;
    }
    if (c.hasBounds) {
        c.boundsMin = lo;
        c.boundsMax = hi;
    }
    return c;
}

// The FeatureSummary flags as (name, value), in declaration order.
std::vector<std::pair<const char*, bool>> featureList(const scene::FeatureSummary& f) {
    return {{"triangles", f.triangles},
            {"spheres", f.spheres},
#define VKP_KIND_FEATURE(id, NAME, Type, key, label, feature, flags, regularized) {#key, f.key},
            VKP_MATERIAL_KINDS(VKP_KIND_FEATURE)
#undef VKP_KIND_FEATURE
                {"emissiveSurfaces", f.emissiveSurfaces},
            {"pointLights", f.pointLights},
            {"spotLights", f.spotLights},
            {"directionalLights", f.directionalLights},
            {"environment", f.environment}};
}

nlohmann::json vecJson(const glm::vec3& v) {
    return {v.x, v.y, v.z};
}

std::string vecText(const glm::vec3& v) {
    return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z);
}

nlohmann::json sceneJson(const std::string& file, const scene::Scene& s, const SceneCounts& c,
                         const KernelPlan& k) {
    nlohmann::json features = nlohmann::json::object();
    for (const auto& [name, value] : featureList(s.features())) features[name] = value;
    nlohmann::json materials = {{"total", s.materials.size()}};
    for (const scene::MaterialKindInfo& kind : scene::MATERIAL_KINDS)
        materials[kind.key] = c.byKind[uint32_t(kind.kind)];
    materials["emissive"] = c.emissive;
    return {
        {"file", file},
        {"triangles", s.triangleCount()},
        {"drawnTriangles", s.drawnTriangleCount()},
        {"meshes", s.meshes.size()},
        {"instances", s.instances.size()},
        {"spheres", s.spheres.size()},
        {"materials", materials},
        {"emitters",
         {{"meshes", c.emissiveMeshes},
          {"spheres", c.emissiveSpheres},
          {"triangles", c.emissiveTriangles}}},
        {"lights",
         {{"point", s.pointLights.size()},
          {"spot", s.spotLights.size()},
          {"directional", s.directionalLights.size()},
          {"environment", s.environment.has_value()}}},
        {"camera",
         {{"name", s.camera.name},
          {"position", vecJson(s.camera.position)},
          {"target", vecJson(s.camera.target)},
          {"up", vecJson(s.camera.up)},
          {"xfovDegrees", s.camera.xfovDegrees},
          {"aspect", s.camera.aspect}}},
        {"bounds",
         c.hasBounds ? nlohmann::json{{"min", vecJson(c.boundsMin)}, {"max", vecJson(c.boundsMax)}}
                     : nlohmann::json(nullptr)},
        {"textures",
         {{"images", s.images.size()}, {"textures", s.textures.size()}, {"texels", c.texels}}},
        {"materialVariants", s.materialVariants},
        {"features", features},
        {"kernelFeatures", wavefront::describeFeatures(k.features)},
        {"deviceBytes",
         {{"scene", k.sceneBytes},
          {"perPathWavefront", k.wavefrontPathBytes},
          {"perPathMegakernel", k.megakernelPathBytes},
          {"perPixelFilm", sizeof(shared::FilmPixel)}}},
    };
}

void printScene(const std::string& file, const scene::Scene& s, const SceneCounts& c,
                const KernelPlan& k) {
    std::printf("scene       %s\n", file.c_str());
    std::printf("triangles   %zu\n", s.triangleCount());
    if (!s.instances.empty())
        std::printf("instances   %zu (%llu triangles drawn)\n", s.instances.size(),
                    (unsigned long long)s.drawnTriangleCount());
    std::printf("meshes      %zu\n", s.meshes.size());
    std::printf("spheres     %zu\n", s.spheres.size());
    std::string kinds;
    for (const scene::MaterialKindInfo& kind : scene::MATERIAL_KINDS)
        kinds += fmt::format("{}{} {}", kinds.empty() ? "" : ", ", kind.label,
                             c.byKind[uint32_t(kind.kind)]);
    std::printf("materials   %zu (%s; emissive %zu)\n", s.materials.size(), kinds.c_str(),
                c.emissive);
    if (!s.materialVariants.empty()) {
        std::string names;
        for (const std::string& name : s.materialVariants)
            names += (names.empty() ? "'" : ", '") + name + "'";
        std::printf("variants    %s (render --variant NAME)\n", names.c_str());
    }
    std::printf("emitters    %zu (meshes %zu, spheres %zu; emissive triangles %zu)\n",
                c.emissiveMeshes + c.emissiveSpheres, c.emissiveMeshes, c.emissiveSpheres,
                c.emissiveTriangles);
    std::printf("lights      point %zu, spot %zu, directional %zu, environment %s\n",
                s.pointLights.size(), s.spotLights.size(), s.directionalLights.size(),
                s.environment ? "yes" : "no");
    std::printf("camera      '%s' position %s target %s up %s xfov %.6g aspect %.6g\n",
                s.camera.name.c_str(), vecText(s.camera.position).c_str(),
                vecText(s.camera.target).c_str(), vecText(s.camera.up).c_str(),
                s.camera.xfovDegrees, s.camera.aspect);
    if (c.hasBounds)
        std::printf("bounds      min %s max %s\n", vecText(c.boundsMin).c_str(),
                    vecText(c.boundsMax).c_str());
    else
        std::printf("bounds      empty\n");
    std::printf("textures    %zu (%zu images, %zu texels)\n", s.textures.size(), s.images.size(),
                c.texels);
    std::string features;
    for (const auto& [name, value] : featureList(s.features()))
        if (value) features += (features.empty() ? "" : " ") + std::string(name);
    std::printf("features    %s\n", features.empty() ? "(none)" : features.c_str());
    std::printf("kernels     specialised to %s (at the default settings)\n",
                wavefront::describeFeatures(k.features).c_str());
    std::printf(
        "memory      scene %llu B on the device; per path in flight: wavefront %llu B, megakernel "
        "%llu B; "
        "film %zu B per pixel\n",
        (unsigned long long)k.sceneBytes, (unsigned long long)k.wavefrontPathBytes,
        (unsigned long long)k.megakernelPathBytes, sizeof(shared::FilmPixel));
}

// The scene as scene-info reads it: refused before its memory is spent
// where it would not fit in the host's (wavefront/scene_footprint.h).
scene::Scene loadSceneForInfo(const std::string& file) {
    scene::LoadOptions load;
    load.admit = [](const std::string& name, const scene::GeometryCounts& counts) {
        wavefront::admitOnHost(name, counts, wavefront::estimateFootprint(counts, false),
                               wavefront::availableHostMemory());
    };
    return scene::loadScene(file, load);
}

}  // namespace

std::string sceneInfoJson(const std::string& file, const scene::Scene& scene) {
    return sceneJson(file, scene, countScene(scene), planKernels(scene)).dump(2);
}

void addSceneInfoCommand(CLI::App& app, const GlobalOptions&, Commands& commands) {
    struct Options {
        std::string file;
        bool json = false;
    };
    auto o = std::make_shared<Options>();
    auto* cmd = app.add_subcommand("scene-info", "Import a scene and summarise what it contains");
    cmd->add_option("FILE", o->file, "Scene file (.gltf, .glb or .dae)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_flag("--json", o->json, "Print JSON instead of text");
    cmd->callback([&commands, o] {
        commands.run = [o] {
            // Bad input throws InputError: runCli prints it as one line, exit 2.
            // It builds the tables the GPU renderer would (planKernels).
            const scene::Scene s = loadSceneForInfo(o->file);
            if (o->json)
                std::printf("%s\n", sceneInfoJson(o->file, s).c_str());
            else
                printScene(o->file, s, countScene(s), planKernels(s));
            return 0;
        };
    });
}

}  // namespace vkpath::app
