// The flags every rendering command shares (`vkpath render`, `vkpath
// converge`): the scene and what replaces its environment or camera, the
// integrator's settings and the device. Each command adds its own flags for
// what it does with the renders (outputs, sample counts).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/film_size.h"
#include "scene/scene.h"
#include "wavefront/render_types.h"

namespace vkpath::vk {
struct DeviceInfo;
}

namespace CLI {
class App;
}

namespace vkpath::app {

// The largest -m and -l renderSettings accepts.
constexpr uint32_t MAX_DEPTH = 1024;
constexpr uint32_t MAX_LIGHT_SAMPLES = 1024;

struct RenderOptions {
    std::string scene;
    std::string size = "640x480";
    uint32_t maxDepth = 8;
    uint32_t lightSamples = 1;
    uint32_t rouletteDepth = wavefront::RenderSettings{}.rouletteDepth;
    uint32_t seed = 0;
    std::string sampler =
        "sobol";  // wavefront::parseSampler's names (the default: RenderSettings's)
    float clamp = 0;
    float regularize = 0;               // path regularisation's least GGX alpha; 0: off
    bool singleScattering = false;      // --single-scattering: no multiple-scattering compensation
    std::string lightSampler = "auto";  // wavefront::parseLightSampling's names
    std::string variant;                // --variant: a glTF material variant; empty: none
    float guideSpheres = wavefront::RenderSettings{}.guideFraction;  // --guide-spheres
    std::string environment;
    std::vector<float> environmentColor;
    std::optional<float> environmentStrength;  // unset: the scene's own (1 for -e)
    std::optional<float> environmentRotation;
    // --fog-*: scene::Scene::fog, one number or R,G,B each; no density: no fog
    std::vector<float> fogDensity;
    std::vector<float> fogAlbedo{1.0f};
    float fogAnisotropy = 0.0f;
    // --volume: an OpenVDB grid medium (scene::Scene::volume); empty: none
    std::string volume;
    std::string volumeGrid = "density";
    float volumeDensity = 1.0f;
    std::vector<float> volumeAlbedo{1.0f};
    float volumeAnisotropy = 0.0f;
    std::string camera;
    std::string instancing = "auto";  // scene::Instancing: auto, on, off
    uint32_t workgroupSize = 64;
    uint32_t megakernelPaths = wavefront::RenderSettings{}.megakernelPathsPerInvocation;
    std::optional<uint32_t> pathsInFlight;     // unset: by the device's type
    std::optional<double> maxWaveMs;           // GPU: RenderSettings::maxWaveMilliseconds
    std::optional<double> maxDeviceMemoryMiB;  // GPU: RenderSettings::maxDeviceMemoryBytes, in MiB
    std::string kernel;          // wavefront::parseKernelForm's names; empty: the device's default
    std::string traversal;       // bvh::parseTraversal's names; empty: the device's default
    bool noSpecialize = false;   // general kernels instead of ones specialised to the scene
    std::string device = "gpu";  // gpu: the Vulkan renderer; cpu: the reference
    std::optional<uint32_t> threads;    // cpu: worker threads (0 or unset: every hardware thread)
    std::optional<double> targetError;  // RenderSettings::targetError
    bool adaptive = false;              // RenderSettings::adaptive
    uint32_t adaptiveWarmup = wavefront::RenderSettings{}.adaptiveWarmup;
};

// Registers the shared flags on `cmd`, the scene as its first positional
// argument, each with the validator of its values (app/validators.h).
void addRenderOptions(CLI::App& cmd, RenderOptions& o);

// The scene file with the flags' environment, fog and camera applied.
// Throws InputError on bad input.
scene::Scene loadRenderScene(const RenderOptions& o);

// One number as grey or three as R,G,B, the values of colour flag `flag`;
// InputError for any other count.
glm::vec3 rgbOf(const std::vector<float>& v, const char* flag);

// The fog the --fog-* flags describe (not present without --fog-density).
// Throws InputError for a value that is neither one number nor three.
scene::Medium fogOf(const RenderOptions& o);

// Refuses, in one line, a scene whose arrays would not fit `device`
// (wavefront::admitOnDevice), counting the acceleration structures where
// the render traces by ray queries.
void admitRenderOnDevice(const RenderOptions& o, const scene::Scene& scene,
                         const vk::DeviceInfo& device);

// What makes renders samples of one image, written into each EXR so that
// `vkpath merge` and `--resume` can refuse parts of different images: a
// hash of the bytes of the scene file, of the files it refers to that its
// loader read (`scene.referencedFiles`) and of the -e environment map, and
// every flag that changes pixels (not outputs, devices or kernels: the CPU
// and GPU render the same samples).
struct RenderIdentity {
    std::string sceneHash;  // 16 hex digits, FNV-1a 64
    // A JSON object, {"size":"640x480","max-depth":8,...,"estimator":N}: each
    // key once, in a fixed order, the estimator's version last.
    std::string settings;
};
RenderIdentity renderIdentity(const RenderOptions& o, const scene::Scene& scene);
// The same from the scene files' hash, sceneFilesHash's (a program that keeps
// a loaded scene computes it once: the files may be gone since).
RenderIdentity renderIdentity(const RenderOptions& o, const std::string& sceneHash);
std::string sceneFilesHash(const RenderOptions& o, const scene::Scene& scene);

// Whether `settings` is a settings record of this format (a JSON object);
// builds before it wrote "key=value" words, which are not.
bool isSettingsRecord(const std::string& settings);

// The first setting in which two RenderIdentity::settings differ, as
// ("key=x's value", "key=y's value"), "nothing" on the side that lacks the
// key (one an older build did not write); two empty strings when they are
// the same. Where either is not a settings record, the two whole strings.
std::pair<std::string, std::string> firstSettingDifference(const std::string& x,
                                                           const std::string& y);

// The settings for `samplesPerPixel` samples of the film `o.size`. Each
// flag's value is checked where it is parsed (addRenderOptions' validators:
// a value out of range never gets here); throws InputError for flags that do
// not go together (-t without --device cpu, --kernel with it) and a film size
// that is not WxH.
wavefront::RenderSettings renderSettings(const RenderOptions& o, uint32_t samplesPerPixel);

}  // namespace vkpath::app
