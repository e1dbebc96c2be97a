#include "app/render_options.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/fnv1a.h"
#include "app/validators.h"
#include "input_error.h"
#include "scene/environment.h"
#include "scene/load.h"
#include "shared/dimensions.h"
#include "wavefront/scene_footprint.h"
#include "wavefront/wave_sizing.h"

namespace vkpath::app {

void addRenderOptions(CLI::App& cmd, RenderOptions& o) {
    // Beyond MAX_DEPTH and MAX_LIGHT_SAMPLES a render runs for hours before its
    // first sample and buys nothing: after 1024 bounces of albedo 0.99 a path
    // keeps 3e-5 of its weight, and 1024 light samples per vertex are 1024
    // shadow rays each.
    cmd.add_option("scene", o.scene, "Scene file (.gltf, .glb, .dae)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd.add_option("-m,--max-depth", o.maxDepth,
                   "Maximum bounces (0: emitters seen directly only, 1: direct lighting)")
        ->check(CLI::Range(0u, MAX_DEPTH))
        ->capture_default_str();
    cmd.add_option("-d,--size", o.size, "Film size WxH")
        ->check(filmSizeValidator())
        ->capture_default_str();
    cmd.add_option("-l,--light-samples", o.lightSamples, "Light samples per diffuse vertex")
        ->check(CLI::Range(0u, MAX_LIGHT_SAMPLES))
        ->capture_default_str();
    cmd.add_option("--rr-depth", o.rouletteDepth,
                   "Russian roulette from this bounce on (unbiased at any depth)")
        ->capture_default_str();
    cmd.add_option("--seed", o.seed, "Random seed")->capture_default_str();
    cmd.add_option("--sampler", o.sampler,
                   "independent: hashed random numbers; sobol: Owen-scrambled Sobol' points, "
                   "stratified per pair of "
                   "dimensions (lower error at equal spp, best at powers of two)")
        ->check(CLI::IsMember({"independent", "sobol"}))
        ->capture_default_str();
    cmd.add_option(
           "--clamp", o.clamp,
           "Clamp each path sample's largest component to this (biased: removes energy; 0: off)")
        ->check(realAtLeast<float>(0))
        ->capture_default_str();
    cmd.add_option("--regularize", o.regularize,
                   "Path regularisation: after a path's first non-delta bounce, widen mirror, "
                   "glass and smooth "
                   "microfacet lobes to at least this GGX alpha, in (0, 1] (biased: blurs "
                   "caustics, removes their "
                   "fireflies; 0: off)")
        ->check(realIn<float>(0, 1))
        ->capture_default_str();
    cmd.add_flag(
        "--single-scattering", o.singleScattering,
        "GGX lobes (rough metal, rough glass, glTF's materials) without multiple-scattering "
        "compensation, as Mitsuba 3 and pbrt-v4 render them: they lose the light that "
        "meets the microsurface again and darken as roughness grows");
    cmd.add_option("--light-sampler", o.lightSampler,
                   "How a light sample chooses its light: power: by power alone; tree: through a "
                   "tree over the lights by what each part of it may send the shaded point; "
                   "auto: the tree where the scene has at least " +
                       std::to_string(wavefront::LIGHT_TREE_MIN_LIGHTS) +
                       " lights with a position (emissive triangles and spheres, point and spot "
                       "lights)")
        ->check(CLI::IsMember({"auto", "power", "tree"}))
        ->capture_default_str();
    cmd.add_option("--guide-spheres", o.guideSpheres,
                   "Share of a diffuse vertex's BSDF samples drawn toward the mirror and glass "
                   "spheres it sees, in "
                   "[0, 1), in scenes with emissive surfaces and no environment map (unbiased: "
                   "finds caustics "
                   "sooner; 0: off)")
        ->check(realIn<float>(
            0, 1, true))  // at 1 no cosine sample is left: light outside the cones would be lost
        ->capture_default_str();
    cmd.add_option("-e,--env", o.environment, "Environment map (.exr, .hdr), equirectangular")
        ->check(CLI::ExistingFile);
    cmd.add_option("--env-color", o.environmentColor, "Constant environment radiance R G B")
        ->expected(3)
        ->delimiter(',');
    cmd.add_option("--env-strength", o.environmentStrength,
                   "Environment multiplier (default: the scene's, or 1)")
        ->check(realAtLeast<float>(0));
    cmd.add_option("--env-rotate", o.environmentRotation,
                   "Environment rotation about +Y, degrees (default: the scene's, or 0)")
        ->check(finiteReal<float>());
    cmd.add_option("--fog-density", o.fogDensity,
                   "A homogeneous fog in all space outside the bodies of transmitting materials: "
                   "its attenuation coefficient per metre (scene unit), one number or R,G,B "
                   "(default: no fog). Rays that leave the scene scatter in it: an environment "
                   "is seen through at most exp(-density x distance)")
        ->expected(1, 3)
        ->delimiter(',')
        ->check(realAtLeast<float>(0));
    cmd.add_option("--fog-albedo", o.fogAlbedo,
                   "The fog's single-scattering albedo, the share of its attenuation that "
                   "scatters (the rest absorbs), in [0, 1], one number or R,G,B")
        ->expected(1, 3)
        ->delimiter(',')
        ->check(realIn<float>(0, 1))
        ->capture_default_str();
    cmd.add_option("--fog-anisotropy", o.fogAnisotropy,
                   "The fog's Henyey-Greenstein g, in (-1, 1): > 0 scatters forward, < 0 back, 0 "
                   "evenly")
        ->check(realIn<float>(-0.999, 0.999))
        ->capture_default_str();
    cmd.add_option("--volume", o.volume,
                   "A heterogeneous medium from an OpenVDB file (.vdb), its float grid placed by "
                   "its own transform, beside the fog (outside the bodies of transmitting "
                   "materials)")
        ->check(CLI::ExistingFile);
    cmd.add_option("--volume-grid", o.volumeGrid, "--volume: the grid's name")
        ->capture_default_str();
    cmd.add_option("--volume-density", o.volumeDensity,
                   "--volume: the attenuation coefficient per metre of a voxel of value 1")
        ->check(realAtLeast<float>(0))
        ->capture_default_str();
    cmd.add_option("--volume-albedo", o.volumeAlbedo,
                   "--volume: the share of the attenuation that scatters, in [0, 1], one number "
                   "or R,G,B")
        ->expected(1, 3)
        ->delimiter(',')
        ->check(realIn<float>(0, 1))
        ->capture_default_str();
    cmd.add_option("--volume-anisotropy", o.volumeAnisotropy,
                   "--volume: the Henyey-Greenstein g, in (-1, 1)")
        ->check(realIn<float>(-0.999, 0.999))
        ->capture_default_str();
    cmd.add_option("--camera", o.camera, "glTF: render from the camera with this name");
    cmd.add_option("--variant", o.variant,
                   "glTF: render the materials of this KHR_materials_variants variant (scene-info "
                   "lists them; default: the primitives' own)");
    cmd.add_option("--instancing", o.instancing,
                   "glTF: keep a mesh that several nodes place once, placed by instances (on), "
                   "copy it per node (off), or instance where the copies would add 2^20 "
                   "triangles or more (auto)")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    cmd.add_option("--workgroup-size", o.workgroupSize,
                   "Threads per workgroup of the stage kernels")
        ->capture_default_str();
    cmd.add_option("--megakernel-paths", o.megakernelPaths,
                   "--kernel megakernel: paths each invocation traces one after another (path "
                   "regeneration; 1: one)")
        ->check(CLI::Range(1u, UINT32_MAX))
        ->capture_default_str();
    cmd.add_option("--paths-in-flight", o.pathsInFlight,
                   "Upper bound on the paths of one wave (default: 16777216 on a discrete GPU, "
                   "1048576 on others)");
    cmd.add_option("--max-wave-ms", o.maxWaveMs,
                   "GPU: size the waves to take at most this many milliseconds each, for drivers "
                   "whose watchdog "
                   "ends long submissions (the image is the same)")
        ->check(realAbove<double>(0));
    cmd.add_option("--max-device-memory", o.maxDeviceMemoryMiB,
                   "GPU: MiB of device memory the scene, film and paths in flight may take, for a "
                   "device shared "
                   "with other work (fewer paths in flight; the image is the same)")
        ->check(realAbove<double>(0));
    cmd.add_option("--kernel", o.kernel,
                   "GPU kernel form: wavefront (stages with queues between them) or megakernel "
                   "(one invocation per "
                   "path); default: the faster on the device's type")
        ->check(CLI::IsMember({"wavefront", "megakernel"}));
    cmd.add_option("--traversal", o.traversal,
                   "GPU: how rays find their hits: compute (the kernels' own BVH traversal) or "
                   "rayquery (the device's acceleration structures, VK_KHR_ray_query; same "
                   "hits but at ties); default: the faster on the device")
        ->check(CLI::IsMember({"compute", "rayquery"}));
    cmd.add_flag("--no-specialize", o.noSpecialize,
                 "The general kernels (GPU) or the general build of the CPU reference, not code "
                 "specialised to "
                 "the scene's features (same image, slower)");
    cmd.add_option("--device", o.device,
                   "gpu: the Vulkan renderer; cpu: the CPU reference (same math)")
        ->check(CLI::IsMember({"gpu", "cpu"}))
        ->capture_default_str();
    cmd.add_option("-t,--threads", o.threads,
                   "--device cpu: worker threads (default: every hardware thread)");
    cmd.add_option("--target-error", o.targetError,
                   "Stop once the image's estimated relMSE (compare's definition, from each "
                   "pixel's variance) is at most this (with -s or --time-budget: whichever "
                   "comes first)")
        ->check(realAbove<double>(0));
    cmd.add_flag("--adaptive", o.adaptive,
                 "Adaptive sampling: after --adaptive-warmup uniform samples, more samples "
                 "where the estimated error is largest (needs --target-error or --time-budget; "
                 "-s is then each pixel's most)");
    cmd.add_option("--adaptive-warmup", o.adaptiveWarmup,
                   "--adaptive: uniform samples of every pixel before any pixel gets more")
        ->check(CLI::Range(1u, UINT32_MAX))
        ->capture_default_str();
}

namespace {

// `hash` continued over a file's bytes.
uint64_t hashFile(const std::string& path, uint64_t hash) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot read", path));
    char buffer[1 << 16];
    while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0)
        hash = fnv1a(std::as_bytes(std::span(buffer, size_t(in.gcount()))), hash);
    return hash;
}

}  // namespace

namespace {

// A float as the double of its shortest decimal form (0.1f as 0.1), so the
// JSON reads as the flag was written and still gives the float back exactly.
double shortest(float v) {
    return std::stod(fmt::format("{}", v));
}

// The settings record, or null for text that is not a JSON object (an older
// build's "key=value" words).
nlohmann::ordered_json parseSettings(const std::string& text) {
    nlohmann::ordered_json record = nlohmann::ordered_json::parse(text, nullptr, false);
    return record.is_object() ? record : nlohmann::ordered_json();
}

// "key=value", a string value without its quotes.
std::string keyValue(const std::string& key, const nlohmann::ordered_json& value) {
    return key + "=" + (value.is_string() ? value.get<std::string>() : value.dump());
}

}  // namespace

std::string sceneFilesHash(const RenderOptions& o, const scene::Scene& scene) {
    uint64_t hash = hashFile(o.scene, FNV1A_OFFSET);
    for (const std::filesystem::path& file : scene.referencedFiles)
        hash = hashFile(file.string(), hash);
    if (!o.environment.empty()) hash = hashFile(o.environment, hash);
    if (!o.volume.empty()) hash = hashFile(o.volume, hash);
    return fmt::format("{:016x}", hash);
}

RenderIdentity renderIdentity(const RenderOptions& o, const scene::Scene& scene) {
    return renderIdentity(o, sceneFilesHash(o, scene));
}

RenderIdentity renderIdentity(const RenderOptions& o, const std::string& sceneHash) {
    auto optional = [](const std::optional<float>& v) {
        return v ? nlohmann::ordered_json(shortest(*v)) : nlohmann::ordered_json("scene");
    };
    nlohmann::ordered_json color = "none";
    if (!o.environmentColor.empty())
        color = {shortest(o.environmentColor[0]), shortest(o.environmentColor[1]),
                 shortest(o.environmentColor[2])};
    nlohmann::ordered_json settings;
    settings["size"] = o.size;
    settings["max-depth"] = o.maxDepth;
    settings["light-samples"] = o.lightSamples;
    settings["rr-depth"] = o.rouletteDepth;
    settings["seed"] = o.seed;
    settings["sampler"] = o.sampler;
    settings["clamp"] = shortest(o.clamp);
    settings["regularize"] = shortest(o.regularize);
    settings["microfacet"] = o.singleScattering ? "single-scattering" : "compensated";
    settings["light-sampler"] = o.lightSampler;
    settings["guide-spheres"] = shortest(o.guideSpheres);
    settings["env"] = o.environment.empty() ? "none" : "file";
    settings["env-color"] = color;
    settings["env-strength"] = optional(o.environmentStrength);
    settings["env-rotate"] = optional(o.environmentRotation);
    settings["camera"] = o.camera.empty() ? "default" : o.camera;
    // Recorded only when chosen, so that checkpoints from before variants resume.
    if (!o.variant.empty()) settings["variant"] = o.variant;
    // Recorded only when there is fog, so that checkpoints from before it resume.
    if (const scene::Medium fog = fogOf(o); fog.present())
        settings["fog"] = {
            {"scattering",
             {shortest(fog.scattering.x), shortest(fog.scattering.y), shortest(fog.scattering.z)}},
            {"absorption",
             {shortest(fog.absorption.x), shortest(fog.absorption.y), shortest(fog.absorption.z)}},
            {"anisotropy", shortest(fog.anisotropy)}};
    // Recorded only with a grid medium (its file is hashed with the scene's).
    if (!o.volume.empty()) {
        const glm::vec3 albedo = rgbOf(o.volumeAlbedo, "--volume-albedo");
        settings["volume"] = {
            {"grid", o.volumeGrid},
            {"density", shortest(o.volumeDensity)},
            {"albedo", {shortest(albedo.x), shortest(albedo.y), shortest(albedo.z)}},
            {"anisotropy", shortest(o.volumeAnisotropy)}};
    }
    // Instanced and copied meshes give the same image up to rounding:
    // recorded only when chosen, so that checkpoints from before instancing resume.
    if (o.instancing != "auto") settings["instancing"] = o.instancing;
    // Which samples each pixel takes (the target error says how many, and
    // with the Sobol' sampler that they come in two streams; recorded only
    // then, so that renders of one stream resume checkpoints from builds
    // before streams).
    if (const uint32_t streams = wavefront::sampleStreams(renderSettings(o, 1)); streams != 1)
        settings["sample-streams"] = streams;
    settings["adaptive"] = o.adaptive ? nlohmann::ordered_json{{"warmup", o.adaptiveWarmup}}
                                      : nlohmann::ordered_json("off");
    settings["estimator"] = VKP_ESTIMATOR_VERSION;
    return {sceneHash, settings.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)};
}

bool isSettingsRecord(const std::string& settings) {
    return !parseSettings(settings).is_null();
}

std::pair<std::string, std::string> firstSettingDifference(const std::string& x,
                                                           const std::string& y) {
    const nlohmann::ordered_json a = parseSettings(x), b = parseSettings(y);
    if (a.is_null() || b.is_null())
        return x == y ? std::pair<std::string, std::string>() : std::pair(x, y);
    // In y's order, then the keys only x has.
    for (const auto& [key, value] : b.items()) {
        if (!a.contains(key)) return {"nothing", keyValue(key, value)};
        if (a[key] != value) return {keyValue(key, a[key]), keyValue(key, value)};
    }
    for (const auto& [key, value] : a.items())
        if (!b.contains(key)) return {keyValue(key, value), "nothing"};
    return {};
}

void admitRenderOnDevice(const RenderOptions& o, const scene::Scene& scene,
                         const vk::DeviceInfo& device) {
    const bvh::Traversal traversal = o.traversal.empty() ? wavefront::defaultTraversal(device)
                                                         : bvh::parseTraversal(o.traversal).value();
    wavefront::admitOnDevice(o.scene,
                             wavefront::estimateFootprint(scene.countGeometry(), false,
                                                          traversal == bvh::Traversal::RayQuery),
                             device);
}

scene::Scene loadRenderScene(const RenderOptions& o) {
    scene::LoadOptions loadOptions;
    loadOptions.cameraName = o.camera;
    loadOptions.materialVariant = o.variant;
    loadOptions.instancing = o.instancing == "on"    ? scene::Instancing::On
                             : o.instancing == "off" ? scene::Instancing::Off
                                                     : scene::Instancing::Auto;
    loadOptions.admit = [&](const std::string& file, const scene::GeometryCounts& counts) {
        wavefront::admitOnHost(file, counts,
                               wavefront::estimateFootprint(counts, o.device == "cpu"),
                               wavefront::availableHostMemory());
    };
    scene::Scene scene = scene::loadScene(o.scene, loadOptions);
    if (!o.environment.empty() || !o.environmentColor.empty()) {
        scene::Environment env;
        if (!o.environment.empty()) env.map = scene::loadEnvironmentMap(o.environment);
        if (!o.environmentColor.empty())
            env.color = {o.environmentColor[0], o.environmentColor[1], o.environmentColor[2]};
        scene.environment = env;
    }
    if (o.environmentStrength && scene.environment)
        scene.environment->strength = *o.environmentStrength;
    if (o.environmentRotation && scene.environment)
        scene.environment->rotationDegrees = *o.environmentRotation;
    scene.fog = fogOf(o);
    if (!o.volume.empty()) {
        scene::VolumeGrid grid = scene::loadVolumeGrid(o.volume, o.volumeGrid);
        grid.densityScale = o.volumeDensity;
        grid.albedo = rgbOf(o.volumeAlbedo, "--volume-albedo");
        grid.anisotropy = o.volumeAnisotropy;
        scene.volume = std::move(grid);
    }
    return scene;
}

glm::vec3 rgbOf(const std::vector<float>& v, const char* flag) {
    if (v.size() == 1) return glm::vec3(v[0]);
    if (v.size() == 3) return glm::vec3(v[0], v[1], v[2]);
    throw InputError(fmt::format("{}: one number or three (R,G,B), not {}", flag, v.size()));
}

scene::Medium fogOf(const RenderOptions& o) {
    scene::Medium fog;
    if (o.fogDensity.empty()) return fog;
    const glm::vec3 density = rgbOf(o.fogDensity, "--fog-density");
    const glm::vec3 albedo = rgbOf(o.fogAlbedo, "--fog-albedo");
    fog.scattering = density * albedo;
    fog.absorption = density - fog.scattering;
    fog.anisotropy = o.fogAnisotropy;
    return fog;
}

wavefront::RenderSettings renderSettings(const RenderOptions& o, uint32_t samplesPerPixel) {
    const FilmSize film = parseFilmSize(o.size);
    if (samplesPerPixel == 0) throw InputError("samples per pixel must be at least 1");
    if (o.threads && o.device != "cpu")
        throw InputError("-t/--threads: only the CPU reference (--device cpu) runs on threads");

    wavefront::RenderSettings settings;
    settings.width = film.width;
    settings.height = film.height;
    settings.samplesPerPixel = samplesPerPixel;
    settings.maxDepth = o.maxDepth;
    settings.lightSamples = o.lightSamples;
    settings.rouletteDepth = o.rouletteDepth;
    settings.seed = o.seed;
    const auto sampler = wavefront::parseSampler(o.sampler);
    if (!sampler)
        throw InputError(
            fmt::format("--sampler: '{}' is neither independent nor sobol", o.sampler));
    settings.sampler = *sampler;
    settings.clampRadiance = o.clamp;
    settings.regularize = o.regularize;
    settings.microfacetCompensation = !o.singleScattering;
    const auto lightSampling = wavefront::parseLightSampling(o.lightSampler);
    if (!lightSampling)
        throw InputError(
            fmt::format("--light-sampler: '{}' is none of auto, power, tree", o.lightSampler));
    settings.lightSampling = *lightSampling;
    settings.guideFraction = o.guideSpheres;
    if (!o.kernel.empty() && o.device == "cpu")
        throw InputError("--kernel chooses a GPU kernel form: not with --device cpu");
    if (!o.kernel.empty()) settings.kernel = wavefront::parseKernelForm(o.kernel);
    if (!o.traversal.empty() && o.device == "cpu")
        throw InputError("--traversal chooses how GPU kernels trace rays: not with --device cpu");
    if (!o.traversal.empty()) settings.traversal = bvh::parseTraversal(o.traversal);
    settings.specialize = !o.noSpecialize;
    settings.workgroupSize = o.workgroupSize;
    settings.megakernelPathsPerInvocation = o.megakernelPaths;
    settings.maxPathsInFlight = o.pathsInFlight;
    settings.maxWaveMilliseconds = o.maxWaveMs;
    if (o.maxDeviceMemoryMiB) {
        // 10^12 MiB (an exabyte) bounds no device, and keeps the bytes in 64 bits.
        settings.maxDeviceMemoryBytes =
            uint64_t(std::min(*o.maxDeviceMemoryMiB, 1e12) * 1024 * 1024);
    }
    settings.threads = o.threads.value_or(0);
    settings.targetError = o.targetError;
    settings.adaptive = o.adaptive;
    settings.adaptiveWarmup = o.adaptiveWarmup;
    return settings;
}

}  // namespace vkpath::app
