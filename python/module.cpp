// vkpath._vkpath: the C++ half of the Python package (python/vkpath/ is the
// other). A render's keywords arrive as `vkpath render`'s own flags and are
// parsed by its own parser (app/render_command.h), so that the same arguments
// give the command line's image bit for bit; the scene is loaded and its BVH
// built once per vkpath.Scene. The shared sampling routines run over numpy
// arrays as GPU kernels (python/kernels/) and as the same C++ functions.
#include <fmt/format.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/render_command.h"
#include "bvh/gpu_bvh.h"
#include "image/denoiser.h"
#include "image/image.h"
#include "image/metrics.h"
#include "image/statistics.h"
#include "input_error.h"
#include "kernels/routines.h"
#include "reference/path_tracer_view.h"
#include "shared/bsdf.h"
#include "shared/rng.h"
#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/embedded_shaders.h"
#include "vk/kernel.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::shaders {
std::span<const EmbeddedShader> pythonKernels();
}

namespace nb = nanobind;
using namespace nb::literals;

namespace vkpath::python {
namespace {

using FloatArray = nb::ndarray<nb::numpy, float>;
using InputArray = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;

// A numpy array that owns `values`, of shape `shape`.
FloatArray ownedArray(std::vector<float> values, std::initializer_list<size_t> shape) {
    auto* owned = new std::vector<float>(std::move(values));
    nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<float>*>(p); });
    return FloatArray(owned->data(), shape, owner);
}

FloatArray imageArray(const image::Image& image) {
    std::vector<float> values(image.pixels.size() * 3);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) values[3 * i + c] = image.pixels[i][c];
    return ownedArray(std::move(values), {image.height, image.width, 3});
}

// An (H, W, 3) array as an image; python/vkpath checks the shape first.
image::Image arrayImage(const InputArray& a) {
    if (a.ndim() != 3 || a.shape(2) != 3) throw InputError("an image array must be (H, W, 3)");
    image::Image image(uint32_t(a.shape(1)), uint32_t(a.shape(0)));
    const float* data = a.data();
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = {data[3 * i], data[3 * i + 1], data[3 * i + 2]};
    return image;
}

// The process's one Vulkan context for every GPU render and routine, made at
// the first use; VKPATH_VALIDATION=1 turns validation on, as for the command.
vk::Context& context() {
    static std::unique_ptr<vk::Context> made;
    if (!made) {
        vk::ContextOptions options;
        const char* validation = std::getenv("VKPATH_VALIDATION");
        options.validation = validation && *validation && std::string(validation) != "0";
        made = std::make_unique<vk::Context>(options);
    }
    return *made;
}

// Raises where a GPU call gave validation messages (tests run with validation on).
class ValidationWatch {
  public:
    ValidationWatch() : m_before(context().validationMessageCount()) {}
    void check() const {
        const uint32_t now = context().validationMessageCount();
        if (now != m_before)
            throw std::runtime_error(
                fmt::format("{} Vulkan validation message(s) (printed above)", now - m_before));
    }

  private:
    uint32_t m_before;
};

// `vkpath render`'s parser over `args` (the scene first, then flags).
// `loaded`: the scene (args' first) was loaded already, and its file need
// not exist any more.
app::RenderCommandOptions parseRenderArgs(const std::vector<std::string>& args,
                                          bool loaded = false) {
    CLI::App cli{"vkpath render", "render"};
    app::RenderCommandOptions o;
    app::addRenderFlags(cli, o);
    if (loaded) cli.get_option("scene")->get_validator()->active(false);
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    try {
        cli.parse(reversed);
    } catch (const CLI::ParseError& e) {
        throw InputError(e.what());
    }
    app::noteGivenFlags(cli, o);
    return o;
}

nb::dict progressDict(const wavefront::RenderProgress& p) {
    nb::dict d;
    d["spp"] = p.samplesDone;
    d["spp_total"] = p.samplesTotal == UINT32_MAX ? nb::none() : nb::cast(p.samplesTotal);
    d["seconds"] = p.seconds;
    d["paths"] = p.paths;
    d["estimated_rel_mse"] = p.estimatedRelMse ? nb::cast(*p.estimatedRelMse) : nb::none();
    return d;
}

// A scene loaded once (with the flags that change it: -e, --env-*, --camera,
// --instancing, --variant)
// and rendered many times; its tables (BVH included) are built at the first
// render and kept.
class Scene {
  public:
    // `sceneArgs`: the file and the flags that change the scene; `device`:
    // the one whose memory it is admitted against (a render may name either).
    Scene(std::vector<std::string> sceneArgs, const std::string& device)
        : m_args(std::move(sceneArgs)) {
        std::vector<std::string> load = m_args;
        load.insert(load.end(), {"--device", device});
        const app::RenderCommandOptions o = parseRenderArgs(load);
        m_path = o.scene;
        nb::gil_scoped_release release;
        m_scene = app::loadRenderScene(o);
        m_sceneHash = app::sceneFilesHash(o, m_scene);
    }

    const std::string& path() const { return m_path; }
    std::string info() const { return app::sceneInfoJson(m_path, m_scene); }

    nb::dict camera() const {
        const scene::Camera& c = m_camera ? *m_camera : m_scene.camera;
        nb::dict d;
        d["position"] = std::vector<float>{c.position.x, c.position.y, c.position.z};
        d["target"] = std::vector<float>{c.target.x, c.target.y, c.target.z};
        d["up"] = std::vector<float>{c.up.x, c.up.y, c.up.z};
        d["fov"] = c.xfovDegrees;
        d["aspect"] = c.aspect;
        return d;
    }

    // World space; scene::Camera's fields (`aspect` 0: the film's).
    void setCamera(std::vector<float> position, std::vector<float> target, std::vector<float> up,
                   float fov, float aspect) {
        if (position.size() != 3 || target.size() != 3 || up.size() != 3)
            throw InputError("camera: position, target and up are three numbers each");
        if (!(fov > 0 && fov < 180)) throw InputError("camera: fov must be in (0, 180) degrees");
        if (!(aspect >= 0 && aspect < 1e6))
            throw InputError("camera: aspect must be 0 or positive");
        scene::Camera c = m_scene.camera;
        c.position = {position[0], position[1], position[2]};
        c.target = {target[0], target[1], target[2]};
        c.up = {up[0], up[1], up[2]};
        c.xfovDegrees = fov;
        c.aspect = aspect;
        if (glm::length(c.target - c.position) == 0 || glm::length(c.up) == 0)
            throw InputError("camera: target equals position, or up is zero");
        m_camera = c;
    }

    // `flags`: the render's own flags (everything but the scene's).
    nb::dict render(const std::vector<std::string>& flags, bool writeFiles, nb::object progress) {
        std::vector<std::string> args = m_args;
        args.insert(args.end(), flags.begin(), flags.end());
        const app::RenderCommandOptions o = parseRenderArgs(args, true);
        if (!m_tables) {
            nb::gil_scoped_release release;
            m_tables = wavefront::buildSceneTables(m_scene);
        }
        wavefront::RenderResult result;
        app::RenderHooks hooks;
        hooks.scene = &m_scene;
        hooks.tables = &*m_tables;
        hooks.sceneHash = m_sceneHash;
        hooks.camera = m_camera;
        hooks.writeFiles = writeFiles;
        hooks.handleSignals = false;
        hooks.result = &result;
        bool interrupted = false, failed = false;
        // Ctrl-C reaches Python's handler, which only flags it; the render
        // asks at every whole sample, and stops there.
        hooks.stopRequested = [&] {
            nb::gil_scoped_acquire acquire;
            if (!failed && !interrupted && PyErr_CheckSignals() != 0) {
                if (PyErr_ExceptionMatches(PyExc_KeyboardInterrupt)) {
                    PyErr_Clear();
                    interrupted = true;
                } else {
                    failed = true;  // left set: raised after the render
                }
            }
            return interrupted || failed;
        };
        if (!progress.is_none())
            hooks.progress = [&](const wavefront::RenderProgress& p) {
                nb::gil_scoped_acquire acquire;
                if (failed) return;
                try {
                    progress(progressDict(p));
                } catch (nb::python_error& e) {
                    if (e.matches(PyExc_KeyboardInterrupt)) {
                        interrupted = true;  // Ctrl-C while the callback ran
                    } else {
                        e.restore();  // raised after the render, which stops at the next sample
                        failed = true;
                    }
                }
            };
        std::optional<ValidationWatch> watch;
        if (o.device == "gpu") {
            hooks.context = &context();
            watch.emplace();
        }
        {
            nb::gil_scoped_release release;
            app::runRender(app::GlobalOptions{}, o, hooks);
        }
        if (failed) throw nb::python_error();
        if (watch) watch->check();
        if (result.samplesPerPixel == 0)
            throw std::runtime_error("stopped before the first whole sample: no image");

        nb::dict out;
        out["image"] = imageArray(result.image);
        out["variance"] = imageArray(result.varianceOfMean);
        const size_t pixels = result.image.pixels.size();
        std::vector<float> spp(pixels, float(result.samplesPerPixel));
        for (size_t i = 0; i < result.pixelSamples.size(); ++i)
            spp[i] = float(result.pixelSamples[i]);
        out["spp"] = ownedArray(std::move(spp), {result.image.height, result.image.width});
        if (!result.albedo.pixels.empty()) {  // --aov albedo or normal, or --denoise
            out["albedo"] = imageArray(result.albedo);
            out["normal"] = imageArray(result.normal);
        }
        out["spp_reached"] = result.samplesPerPixel;
        out["seconds"] = result.seconds;
        out["paths"] = result.paths;
        out["estimated_rel_mse"] =
            result.estimatedRelMse ? nb::cast(*result.estimatedRelMse) : nb::none();
        out["reached_target"] = result.reachedTarget;
        out["stopped"] = result.stopped;
        out["interrupted"] = interrupted;
        out["non_finite_samples"] = result.nonFiniteSamples;
        if (o.denoise) {
            image::Denoised denoised;
            {
                nb::gil_scoped_release release;
                // Guided and prefiltered as render --denoise is (render_command.cpp).
                denoised = image::denoise(
                    image::DenoiseInputs{&result.image, &result.albedo, &result.normal, true});
            }
            out["denoised"] = imageArray(denoised.image);
        }
        return out;
    }

    // sampleSceneLight from each of `points` (world space) and the
    // environment's density and radiance in each of `directions`.
    nb::dict lights(const InputArray& points, const InputArray& directions, uint32_t seed,
                    const std::string& sampler, uint32_t sampleIndex, const std::string& device) {
        const size_t n = points.shape(0);
        for (const InputArray* a : {&points, &directions})
            if (a->ndim() != 2 || a->shape(0) != n || a->shape(1) != 3)
                throw InputError("points and directions must be (N, 3) arrays of one N");
        if (n == 0 || n > (size_t(1) << 26))
            throw InputError("between 1 and 2^26 inputs at a time");
        if (device != "gpu" && device != "cpu")
            throw InputError(fmt::format("device '{}' is neither gpu nor cpu", device));
        const auto kind = wavefront::parseSampler(sampler);
        if (!kind)
            throw InputError(fmt::format("sampler '{}' is neither independent nor sobol", sampler));
        if (!m_tables) {
            nb::gil_scoped_release release;
            m_tables = wavefront::buildSceneTables(m_scene);
        }
        wavefront::RenderSettings settings;
        settings.seed = seed;
        settings.sampler = *kind;
        const shared::SceneInfo info = wavefront::renderSceneInfo(*m_tables, settings);
        if (info.lightCount == 0) throw InputError(fmt::format("{}: no light to sample", m_path));
        std::vector<shared::LightRoutineInput> inputs(n);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                inputs[i].point[c] =
                    float(double(points.data()[3 * i + c]) - m_tables->worldOrigin[c]);
                inputs[i].direction[c] = directions.data()[3 * i + c];
            }
        const shared::LightRoutinePush push{uint32_t(n), seed, uint32_t(*kind), sampleIndex};
        std::vector<shared::LightRoutineOutput> outputs(n);
        if (device == "gpu") {
            const ValidationWatch watch;
            vk::Context& ctx = context();
            const wavefront::GpuScene scene = wavefront::uploadScene(ctx, *m_tables);
            std::vector<std::byte> infoBytes(sizeof(info) +
                                             info.guideSphereCount * sizeof(glm::vec4));
            std::memcpy(infoBytes.data(), &info, sizeof(info));
            if (info.guideSphereCount > 0)
                std::memcpy(infoBytes.data() + sizeof(info), m_tables->guideSpheres.data(),
                            info.guideSphereCount * sizeof(glm::vec4));
            vk::Buffer infoBuffer = vk::Buffer::fromSpan(ctx, std::span(infoBytes), "sceneInfo");
            vk::Buffer in = vk::Buffer::fromSpan(ctx, std::span(inputs), "light inputs");
            vk::Buffer out(ctx, n * sizeof(shared::LightRoutineOutput));
            std::map<uint32_t, const vk::Buffer*> bindings = {{VKP_WF_SCENE_INFO, &infoBuffer},
                                                              {VKP_ROUTINE_INPUTS, &in},
                                                              {VKP_ROUTINE_OUTPUTS, &out}};
            for (const auto& [binding, buffer] : scene.bindings()) bindings[binding] = buffer;
            vk::KernelOptions options;
            options.specialization = {bvh::sceneAccessConstant(scene.byAddress)};
            vk::Kernel kernel(ctx, "light_routine", options);
            const vk::DescriptorSet set = kernel.bindDeclared(bindings);
            {
                nb::gil_scoped_release release;
                ctx.submit([&](VkCommandBuffer cmd) {
                    kernel.record(cmd, set, uint32_t(n), std::as_bytes(std::span(&push, 1)));
                });
            }
            outputs = out.download<shared::LightRoutineOutput>();
            watch.check();
        } else {
            nb::gil_scoped_release release;
            const shared::PathTracerView view(*m_tables, info);
            for (size_t i = 0; i < n; ++i) {
                const shared::LightRoutineInput& a = inputs[i];
                const shared::RngKey key =
                    shared::makeRngKey(uint32_t(i), sampleIndex, seed, uint32_t(*kind));
                const auto chosen =
                    view.sampleSceneLight(a.point, glm::vec3(0.0f), key, 0);  // no surface
                shared::LightRoutineOutput& r = outputs[i];
                r.direction = chosen.lightSample.direction;
                r.distance = chosen.lightSample.distance;
                r.radiance = chosen.lightSample.radiance;
                r.pdf = chosen.lightSample.pdf;
                r.normal = chosen.lightSample.normal;
                r.choice = chosen.choice;
                r.lightIndex = chosen.lightIndex;
                r.delta = chosen.lightSample.delta ? 1u : 0u;
                r.environmentRadiance = view.environmentRadiance(a.direction);
                r.environmentPdf = view.environmentPdf(a.direction);
            }
        }
        std::vector<float> direction(3 * n), radiance(3 * n), normal(3 * n), envRadiance(3 * n),
            distance(n), pdf(n), choice(n), light(n), delta(n), envPdf(n);
        for (size_t i = 0; i < n; ++i) {
            const shared::LightRoutineOutput& r = outputs[i];
            for (int c = 0; c < 3; ++c) {
                direction[3 * i + c] = r.direction[c];
                radiance[3 * i + c] = r.radiance[c];
                normal[3 * i + c] = r.normal[c];
                envRadiance[3 * i + c] = r.environmentRadiance[c];
            }
            distance[i] = r.distance;
            pdf[i] = r.pdf;
            choice[i] = r.choice;
            light[i] = r.lightIndex == VKP_NO_LIGHT ? -1.0f : float(r.lightIndex);
            delta[i] = float(r.delta);
            envPdf[i] = r.environmentPdf;
        }
        nb::dict d;
        d["direction"] = ownedArray(std::move(direction), {n, 3});
        d["distance"] = ownedArray(std::move(distance), {n});
        d["radiance"] = ownedArray(std::move(radiance), {n, 3});
        d["pdf"] = ownedArray(std::move(pdf), {n});
        d["normal"] = ownedArray(std::move(normal), {n, 3});
        d["choice"] = ownedArray(std::move(choice), {n});
        d["light"] = ownedArray(std::move(light), {n});
        d["delta"] = ownedArray(std::move(delta), {n});
        d["environment_radiance"] = ownedArray(std::move(envRadiance), {n, 3});
        d["environment_pdf"] = ownedArray(std::move(envPdf), {n});
        return d;
    }

  private:
    std::vector<std::string> m_args;
    std::string m_path;
    scene::Scene m_scene;
    std::string m_sceneHash;  // of the files it was loaded from (app::sceneFilesHash)
    std::optional<wavefront::SceneTables> m_tables;
    std::optional<scene::Camera> m_camera;
};

nb::dict metricsDict(const image::ChannelMetrics& m) {
    nb::dict d;
    d["rmse"] = m.rmse;
    d["rel_mse"] = m.relMse;
    d["rel_mse_trimmed"] = m.relMseTrimmed;
    d["mae"] = m.mae;
    d["max_error"] = m.maxError;
    d["max_at"] = std::vector<uint32_t>{m.maxX, m.maxY};
    d["psnr"] = m.psnr;
    return d;
}

nb::dict compare(const InputArray& a, const InputArray& b) {
    const image::ImageMetrics m = image::compareImages(arrayImage(a), arrayImage(b));
    nb::dict d = metricsDict(m.overall);
    nb::list channels;
    for (const auto& c : m.channels) channels.append(metricsDict(c));
    d["channels"] = channels;
    d["non_finite_a"] = m.nonFiniteA;
    d["non_finite_b"] = m.nonFiniteB;
    return d;
}

nb::dict zTest(const InputArray& a, const InputArray& varianceA, const InputArray& b,
               const InputArray& varianceB, double alpha, uint32_t blockSize) {
    if (!(alpha > 0 && alpha < 1)) throw InputError("alpha must be in (0, 1)");
    if (blockSize == 0) throw InputError("block_size must be at least 1");
    const image::BlockComparison c =
        image::compareBlocks(arrayImage(a), arrayImage(varianceA), arrayImage(b),
                             arrayImage(varianceB), blockSize, alpha);
    nb::dict d;
    d["blocks"] = c.blocks;
    d["block_size"] = blockSize;
    d["alpha"] = c.alpha;
    d["critical"] = c.critical;
    d["rejected"] = c.rejected;
    d["worst_z"] = c.worstZ;
    d["worst_block"] = std::vector<uint32_t>{c.worstX, c.worstY};
    d["same"] = c.rejected == 0;
    return d;
}

nb::dict readExr(const std::string& path) {
    nb::dict d;
    d["image"] = imageArray(image::readImage(path));
    nb::dict metadata;
    for (const auto& [key, value] : image::readVkpathMetadata(path)) metadata[key.c_str()] = value;
    d["metadata"] = metadata;
    return d;
}

void writeExr(const std::string& path, const InputArray& a) {
    image::writeExr(path, arrayImage(a));
}

// ---- the shared routines over arrays ---------------------------------------------------

glm::vec3 vec3Of(const nb::dict& d, const char* key, glm::vec3 fallback) {
    if (!d.contains(key)) return fallback;
    const auto v = nb::cast<std::vector<float>>(d[key]);
    if (v.size() != 3) throw InputError(fmt::format("material: {} must be three numbers", key));
    return {v[0], v[1], v[2]};
}

float floatOf(const nb::dict& d, const char* key, float fallback) {
    return d.contains(key) ? nb::cast<float>(d[key]) : fallback;
}

// A material given as scene::Material's fields (python/vkpath/__init__.py
// lists them), made into the kernels' record by the host's own conversion.
shared::Material materialOf(const nb::dict& d) {
    static const char* const known[] = {
        "kind",     "reflectance",    "transmittance", "ior",         "roughness",  "metallic",
        "specular", "specular_color", "conductor_eta", "conductor_k", "attenuation"};
    for (auto [key, value] : d) {
        const std::string name = nb::cast<std::string>(key);
        if (std::find_if(std::begin(known), std::end(known),
                         [&](const char* k) { return name == k; }) == std::end(known))
            throw InputError(fmt::format("material: unknown field '{}'", name));
    }
    scene::Material m;
    const std::string kind = d.contains("kind") ? nb::cast<std::string>(d["kind"]) : "diffuse";
    bool found = false;
    std::string kinds;
    for (const scene::MaterialKindInfo& info : scene::MATERIAL_KINDS) {
        kinds += (kinds.empty() ? "" : ", ") + std::string(info.key);
        if (kind == info.key) {
            m.kind = info.kind;
            found = true;
        }
    }
    if (!found) throw InputError(fmt::format("material: kind '{}' is not one of {}", kind, kinds));
    m.reflectance = vec3Of(d, "reflectance", m.reflectance);
    m.transmittance = vec3Of(d, "transmittance", m.transmittance);
    m.ior = floatOf(d, "ior", m.ior);
    m.roughness = floatOf(d, "roughness", m.roughness);
    m.metallic = floatOf(d, "metallic", m.metallic);
    m.specular = floatOf(d, "specular", m.specular);
    m.specularColor = vec3Of(d, "specular_color", m.specularColor);
    m.conductorEta = vec3Of(d, "conductor_eta", m.conductorEta);
    m.conductorK = vec3Of(d, "conductor_k", m.conductorK);
    m.attenuation = vec3Of(d, "attenuation", m.attenuation);
    if (!(m.ior >= 1.0f && m.ior < 1e4f)) throw InputError("material: ior must be in [1, 1e4)");
    for (float v : {m.roughness, m.metallic, m.specular})
        if (!(v >= 0 && v <= 1))
            throw InputError("material: roughness, metallic and specular must be in [0, 1]");
    scene::Scene s;
    s.materials.push_back(m);
    s.spheres.push_back({"ball", glm::vec3(0.0f), 1.0f, 0});
    return wavefront::buildSceneTables(s).materials.at(0);
}

// wo, wi and u: (N, 3) each; the outputs as arrays. `atSample`: eval and
// eval_pdf at each sampled direction instead of at wi.
nb::dict bsdf(const nb::dict& material, const InputArray& wo, const InputArray& wi,
              const InputArray& u, bool atSample, const std::string& device) {
    const size_t n = wo.shape(0);
    for (const InputArray* a : {&wo, &wi, &u})
        if (a->ndim() != 2 || a->shape(0) != n || a->shape(1) != 3)
            throw InputError("wo, wi and u must be (N, 3) arrays of one N");
    if (n == 0 || n > (size_t(1) << 26)) throw InputError("between 1 and 2^26 inputs at a time");
    if (device != "gpu" && device != "cpu")
        throw InputError(fmt::format("device '{}' is neither gpu nor cpu", device));
    const shared::Material m = materialOf(material);
    std::vector<shared::BsdfRoutineInput> inputs(n);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            inputs[i].wo[c] = wo.data()[3 * i + c];
            inputs[i].wi[c] = wi.data()[3 * i + c];
            inputs[i].u[c] = u.data()[3 * i + c];
        }
    std::vector<shared::BsdfRoutineOutput> outputs(n);
    if (device == "gpu") {
        const ValidationWatch watch;
        vk::Context& ctx = context();
        vk::Buffer in = vk::Buffer::fromSpan(ctx, std::span(inputs), "bsdf inputs");
        vk::Buffer out(ctx, n * sizeof(shared::BsdfRoutineOutput));
        vk::Buffer materials = vk::Buffer::fromSpan(ctx, std::span(&m, 1), "material");
        vk::Kernel kernel(ctx, "bsdf_routine");
        const shared::BsdfRoutinePush push{uint32_t(n), atSample ? 1u : 0u};
        {
            nb::gil_scoped_release release;
            kernel.dispatch(uint32_t(n), {{0, &in}, {1, &out}, {2, &materials}}, push);
        }
        outputs = out.download<shared::BsdfRoutineOutput>();
        watch.check();
    } else {
        nb::gil_scoped_release release;
        const glm::vec3 normal(0, 0, 1);
        for (size_t i = 0; i < n; ++i) {
            const shared::BsdfRoutineInput& a = inputs[i];
            const shared::BsdfSample s =
                shared::sampleBsdf(m, normal, normal, a.wo, glm::vec2(a.u), a.u.z);
            shared::BsdfRoutineOutput& r = outputs[i];
            r.direction = s.direction;
            r.pdf = s.pdf;
            r.weight = s.weight;
            r.flags = (s.valid ? 1u : 0u) | (s.delta ? 2u : 0u);
            r.etaSquared = s.etaSquared;
            const glm::vec3 at = atSample ? s.direction : a.wi;
            const bool evaluated = !atSample || s.valid;
            r.eval = evaluated ? shared::evalBsdf(m, normal, normal, a.wo, at) : glm::vec3(0.0f);
            r.evalPdf = evaluated ? shared::bsdfPdf(m, normal, normal, a.wo, at) : 0.0f;
        }
    }
    std::vector<float> direction(3 * n), weight(3 * n), eval(3 * n), pdf(n), evalPdf(n), valid(n),
        delta(n);
    for (size_t i = 0; i < n; ++i) {
        const shared::BsdfRoutineOutput& r = outputs[i];
        for (int c = 0; c < 3; ++c) {
            direction[3 * i + c] = r.direction[c];
            weight[3 * i + c] = r.weight[c];
            eval[3 * i + c] = r.eval[c];
        }
        pdf[i] = r.pdf;
        evalPdf[i] = r.evalPdf;
        valid[i] = (r.flags & 1u) ? 1.0f : 0.0f;
        delta[i] = (r.flags & 2u) ? 1.0f : 0.0f;
    }
    nb::dict d;
    d["direction"] = ownedArray(std::move(direction), {n, 3});
    d["weight"] = ownedArray(std::move(weight), {n, 3});
    d["pdf"] = ownedArray(std::move(pdf), {n});
    d["valid"] = ownedArray(std::move(valid), {n});
    d["delta"] = ownedArray(std::move(delta), {n});
    d["eval"] = ownedArray(std::move(eval), {n, 3});
    d["eval_pdf"] = ownedArray(std::move(evalPdf), {n});
    return d;
}

// (samples, dimensions, pixels) values of the sampler.
FloatArray samplerValues(const std::string& sampler, uint32_t seed, uint32_t pixels,
                         uint32_t samples, uint32_t dimensions, uint32_t firstSample,
                         const std::string& device) {
    const auto kind = wavefront::parseSampler(sampler);
    if (!kind)
        throw InputError(fmt::format("sampler '{}' is neither independent nor sobol", sampler));
    if (device != "gpu" && device != "cpu")
        throw InputError(fmt::format("device '{}' is neither gpu nor cpu", device));
    const uint64_t count = uint64_t(pixels) * samples * dimensions;
    if (count == 0 || count > (uint64_t(1) << 28))
        throw InputError("pixels x samples x dimensions must be between 1 and 2^28");
    const shared::SamplerValuesPush push{uint32_t(count), pixels,     dimensions, seed,
                                         uint32_t(*kind), firstSample};
    std::vector<float> values(count);
    if (device == "gpu") {
        const ValidationWatch watch;
        vk::Context& ctx = context();
        vk::Buffer out(ctx, count * sizeof(float));
        vk::Kernel kernel(ctx, "sampler_values");
        {
            nb::gil_scoped_release release;
            kernel.dispatch(uint32_t(count), {{0, &out}}, push);
        }
        values = out.download<float>();
        watch.check();
    } else {
        nb::gil_scoped_release release;
        for (uint64_t i = 0; i < count; ++i) {
            const uint32_t pixel = uint32_t(i % pixels);
            const uint32_t dimension = uint32_t((i / pixels) % dimensions);
            const uint32_t sampleIndex =
                firstSample + uint32_t(i / (uint64_t(pixels) * dimensions));
            values[i] = shared::rngUniform(
                shared::makeRngKey(pixel, sampleIndex, seed, uint32_t(*kind)), dimension);
        }
    }
    return ownedArray(std::move(values), {samples, dimensions, pixels});
}

}  // namespace
}  // namespace vkpath::python

NB_MODULE(_vkpath, m) {
    using namespace vkpath::python;
    vkpath::shaders::registerKernels(vkpath::shaders::pythonKernels());
    // The command line's one-line messages, as Python exceptions.
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const vkpath::InputError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const vkpath::vk::VulkanError& e) {
            PyErr_SetString(PyExc_RuntimeError, (std::string("Vulkan error: ") + e.what()).c_str());
        }
    });
    m.attr("__version__") = VKPATH_VERSION;
    std::vector<std::string> kinds;  // the material registry's keys (shared/material_kinds.h)
    for (const vkpath::scene::MaterialKindInfo& info : vkpath::scene::MATERIAL_KINDS)
        kinds.emplace_back(info.key);
    m.attr("MATERIAL_KINDS") = kinds;

    nb::class_<Scene>(m, "Scene")
        .def(nb::init<std::vector<std::string>, const std::string&>(), "scene_args"_a, "device"_a)
        .def_prop_ro("path", &Scene::path)
        .def("info", &Scene::info)
        .def("camera", &Scene::camera)
        .def("set_camera", &Scene::setCamera, "position"_a, "target"_a, "up"_a, "fov"_a, "aspect"_a)
        .def("render", &Scene::render, "flags"_a, "write_files"_a, "progress"_a.none())
        .def("lights", &Scene::lights, "points"_a, "directions"_a, "seed"_a, "sampler"_a,
             "sample_index"_a, "device"_a);
    m.def("compare", &compare, "a"_a, "b"_a);
    m.def("z_test", &zTest, "a"_a, "variance_a"_a, "b"_a, "variance_b"_a, "alpha"_a,
          "block_size"_a);
    m.def("read_exr", &readExr, "path"_a);
    m.def("write_exr", &writeExr, "path"_a, "image"_a);
    m.def("bsdf", &bsdf, "material"_a, "wo"_a, "wi"_a, "u"_a, "at_sample"_a, "device"_a);
    m.def("sampler_values", &samplerValues, "sampler"_a, "seed"_a, "pixels"_a, "samples"_a,
          "dimensions"_a, "first_sample"_a, "device"_a);
}
