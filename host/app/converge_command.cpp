// `vkpath converge SCENE --spp 1,2,4,...`: how fast a render's error falls
// with time. One progressive render per configuration (sample ranges
// rendered one after another and merged, so every checkpoint continues the
// last), its error at each checkpoint against a reference or, without one,
// estimated from a second render with another seed; a CSV, a log-log plot
// and the time each configuration needs to reach a given error.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/glm.hpp>
#include <memory>
#include <optional>

#include "app/commands.h"
#include "app/convergence.h"
#include "app/render_options.h"
#include "app/validators.h"
#include "image/denoiser.h"
#include "image/image.h"
#include "image/metrics.h"
#include "input_error.h"
#include "plot/plot.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "vk/context.h"
#include "wavefront/renderer.h"
#include "wavefront/sample_schedule.h"
#include "wavefront/scene_footprint.h"

namespace vkpath::app {
namespace {

using Clock = std::chrono::steady_clock;

struct ConvergeOptions : RenderOptions {
    std::string spp = "1,2,4,8,16,32";
    std::string reference;
    std::string csv = "out/converge.csv";
    std::string plot = "out/converge.png";
    std::string sweep;
    std::string metric = "relmse";  // what the tables and the plot use: relmse or trimmed-relmse
    bool denoise = false;           // each checkpoint's image denoised (image/denoiser.h)
};

// The relMSE levels of the time-to-error table.
constexpr double TARGETS[] = {1e-1, 1e-2, 1e-3};

struct Configuration {
    std::string knob, value;  // empty without --sweep
    std::string label;
    wavefront::RenderSettings settings;
    std::vector<Checkpoint> curve;
};

// The curves as the tables and the plot see them: with `trimmed`, each
// checkpoint's relMSE is the trimmed one (the CSV keeps both).
std::vector<Configuration> tabulated(std::vector<Configuration> configs, bool trimmed) {
    if (trimmed)
        for (Configuration& c : configs)
            for (Checkpoint& p : c.curve) p.relMse = p.relMseTrimmed;
    return configs;
}

// One renderer's samples so far: each range it renders is added to running
// sums (of the samples and their squares) weighted by its sample count; the
// cost is the wall clock of
// the render calls (film read-back included, as a progressive viewer pays
// it) and, on the GPU, their summed stage timestamps.
template <typename Renderer>
class Progressive {
  public:
    Progressive(std::unique_ptr<Renderer> renderer, uint32_t pixels)
        : m_renderer(std::move(renderer)),
          m_sum(pixels, glm::dvec3(0.0)),
          m_sumSquares(pixels, glm::dvec3(0.0)) {}

    // An untimed first sample: the first dispatches of a process compile the
    // kernels a pipeline cache lacks (seconds on lavapipe), which is no cost
    // of the samples.
    void warmUp() { m_renderer->render(wavefront::SampleRange{0, 1}); }

    void advanceTo(uint32_t spp) {
        const auto start = Clock::now();
        const wavefront::RenderResult result =
            m_renderer->render(wavefront::SampleRange{m_samples, spp - m_samples});
        m_wallSeconds += std::chrono::duration<double>(Clock::now() - start).count();
        for (const auto& [stage, ms] : result.stageMilliseconds) m_deviceSeconds += ms * 1e-3;
        // A range's n samples of mean m and variance of the mean v sum to n m,
        // their squares to n (v (n - 1) + m^2) (wavefront::estimatePixel undone).
        const double n = result.samplesPerPixel;
        for (size_t i = 0; i < m_sum.size(); ++i) {
            const glm::dvec3 m(result.image.pixels[i]), v(result.varianceOfMean.pixels[i]);
            m_sum[i] += m * n;
            m_sumSquares[i] += n * (v * (n - 1) + m * m);
        }
        // The AOVs (the denoiser's guides), weighted alike.
        if (!result.albedo.pixels.empty()) {
            m_albedoSum.resize(m_sum.size(), glm::dvec3(0.0));
            m_normalSum.resize(m_sum.size(), glm::dvec3(0.0));
            for (size_t i = 0; i < m_sum.size(); ++i) {
                m_albedoSum[i] += glm::dvec3(result.albedo.pixels[i]) * n;
                m_normalSum[i] += glm::dvec3(result.normal.pixels[i]) * n;
            }
        }
        m_samples += result.samplesPerPixel;
        m_width = result.image.width;
        m_height = result.image.height;
    }

    image::Image mean() const { return meanOf(m_sum); }
    // The mean albedo and normal AOVs (renders with RenderSettings::surfaceAovs).
    image::Image albedo() const { return meanOf(m_albedoSum); }
    image::Image normal() const { return meanOf(m_normalSum); }
    // The error the render estimates from its own variance.
    double estimatedRelMse() const {
        std::vector<wavefront::PixelStatistics> stats(m_sum.size());
        for (size_t i = 0; i < m_sum.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const wavefront::PixelEstimate e =
                    wavefront::estimatePixel(m_sum[i][c], m_sumSquares[i][c], m_samples);
                stats[i].mean[c] = e.mean;
                stats[i].varianceOfMean[c] = e.varianceOfMean;
            }
        return wavefront::estimatedRelMse(stats, m_width, m_height);
    }
    double wallSeconds() const { return m_wallSeconds; }
    double deviceSeconds() const { return m_deviceSeconds; }

  private:
    image::Image meanOf(const std::vector<glm::dvec3>& sums) const {
        image::Image image(m_width, m_height);
        for (size_t i = 0; i < sums.size(); ++i)
            image.pixels[i] = glm::vec3(sums[i] / double(m_samples));
        return image;
    }

    std::unique_ptr<Renderer> m_renderer;
    std::vector<glm::dvec3> m_sum, m_sumSquares;
    std::vector<glm::dvec3> m_albedoSum, m_normalSum;
    uint32_t m_samples = 0;
    uint32_t m_width = 0, m_height = 0;
    double m_wallSeconds = 0, m_deviceSeconds = 0;
};

// The curve of one configuration. Without a reference a second renderer
// with seed + 1 follows the first, checkpoint by checkpoint; its cost is
// not counted (it only measures the first). `gpu`: record device times, and
// warm up before the first configuration. With `targetError` the curve ends
// at the first checkpoint from wavefront::FIRST_ERROR_CHECK spp on whose own
// estimate reaches it. With `denoise` each checkpoint's image is denoised,
// guided by the albedo and normal AOVs rendered with it (as render
// --denoise), before it is measured, and the denoiser's time is added to its
// own.
template <typename Renderer, typename Make>
std::vector<Checkpoint> measure(const Make& make, const Configuration& config,
                                const std::vector<uint32_t>& spp,
                                const std::optional<image::Image>& reference, bool gpu, bool first,
                                std::optional<double> targetError, bool denoise) {
    const uint32_t pixels = config.settings.width * config.settings.height;
    wavefront::RenderSettings settings = config.settings;
    settings.surfaceAovs = denoise;
    Progressive<Renderer> a(make(settings), pixels);
    if (gpu && first) a.warmUp();
    std::optional<Progressive<Renderer>> b;
    if (!reference) {
        wavefront::RenderSettings other = config.settings;
        other.seed += 1;
        b.emplace(make(other), pixels);
    }
    std::vector<Checkpoint> curve;
    for (uint32_t n : spp) {
        a.advanceTo(n);
        Checkpoint c;
        c.spp = n;
        c.wallSeconds = a.wallSeconds();
        if (gpu) c.deviceSeconds = a.deviceSeconds();
        image::ChannelMetrics error;
        if (denoise) {  // converge checks that there is a reference
            const image::Image mean = a.mean(), albedo = a.albedo(), normal = a.normal();
            const image::Denoised denoised = image::denoise({&mean, &albedo, &normal, true});
            c.wallSeconds += denoised.seconds;
            error = image::compareImages(denoised.image, *reference).overall;
        } else if (reference) {
            error = image::compareImages(a.mean(), *reference).overall;
        } else {
            b->advanceTo(n);
            error = image::estimateErrorFromPair(a.mean(), b->mean());
        }
        c.relMse = error.relMse;
        c.rmse = error.rmse;
        c.relMseTrimmed = error.relMseTrimmed;
        c.estimatedRelMse = a.estimatedRelMse();
        std::fprintf(stderr, "%s: %u spp, %.3f s, relMSE %.4g (trimmed %.4g, estimated %.4g)\n",
                     config.label.c_str(), n, c.wallSeconds, c.relMse, c.relMseTrimmed,
                     c.estimatedRelMse);
        curve.push_back(c);
        if (targetError && n >= wavefront::FIRST_ERROR_CHECK && c.estimatedRelMse <= *targetError)
            break;
    }
    return curve;
}

void ensureParent(const std::filesystem::path& path) {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
}

void writeCsv(const std::filesystem::path& path, const std::vector<Configuration>& configs,
              const std::string& errorSource) {
    ensureParent(path);
    const std::filesystem::path temporary = path.string() + ".tmp";
    {
        std::ofstream out(temporary);
        out << "knob,value,spp,wall_seconds,device_seconds,relmse,rmse,relmse_trimmed,error,"
               "estimated_relmse\n";
        for (const Configuration& config : configs)
            for (const Checkpoint& c : config.curve)
                out << fmt::format("{},{},{},{:.6f},{},{:.6g},{:.6g},{:.6g},{},{:.6g}\n",
                                   config.knob, config.value, c.spp, c.wallSeconds,
                                   c.deviceSeconds ? fmt::format("{:.6f}", *c.deviceSeconds) : "",
                                   c.relMse, c.rmse, c.relMseTrimmed, errorSource,
                                   c.estimatedRelMse);
        if (!out) throw std::runtime_error(fmt::format("{}: cannot write", path.string()));
    }
    std::filesystem::rename(temporary, path);
}

void printTables(const std::vector<Configuration>& configs, const char* metric) {
    size_t width = std::string("configuration").size();
    for (const Configuration& c : configs) width = std::max(width, c.label.size());
    std::printf(
        "time to reach %s (wall seconds, interpolated on log-log axes between checkpoints)\n",
        metric);
    std::printf("%-*s", int(width), "configuration");
    for (double target : TARGETS) std::printf("  %12s", fmt::format("{:g}", target).c_str());
    std::printf("\n");
    for (const Configuration& c : configs) {
        std::printf("%-*s", int(width), c.label.c_str());
        for (double target : TARGETS) {
            const auto t = timeToRelMse(c.curve, target);
            const std::string cell =
                !t ? "not reached"
                   : fmt::format("{}{:.3g} s", c.curve.front().relMse <= target ? "<= " : "", *t);
            std::printf("  %12s", cell.c_str());
        }
        std::printf("\n");
    }

    std::printf("\nefficiency at the last checkpoint: 1 / (wall seconds x %s)\n", metric);
    double best = 0;
    for (const Configuration& c : configs) best = std::max(best, efficiency(c.curve));
    std::printf("%-*s  %6s  %10s  %10s  %12s\n", int(width), "configuration", "spp", "wall s",
                "relMSE", "efficiency");
    for (const Configuration& c : configs) {
        const Checkpoint& last = c.curve.back();
        const double e = efficiency(c.curve);
        std::printf("%-*s  %6u  %10.3f  %10.4g  %12.4g%s\n", int(width), c.label.c_str(), last.spp,
                    last.wallSeconds, last.relMse, e,
                    configs.size() > 1 && e == best ? "  <- best" : "");
    }
}

int runConverge(const GlobalOptions& global, const ConvergeOptions& o) {
    const std::vector<uint32_t> spp = parseSppList(o.spp);
    if (o.adaptive)
        throw InputError(
            "--adaptive: converge measures one uniform render in sample ranges; measure adaptive "
            "renders with render --adaptive --target-error");
    wavefront::RenderSettings base = renderSettings(o, spp.back());
    // The curve's stop (measure), not each range's. Its estimate is the
    // samples' variance, merged over the ranges: one stream, so with Sobol'
    // points an upper bound (docs/ACCURACY.md).
    base.targetError.reset();
    std::vector<Configuration> configs;
    if (o.sweep.empty()) {
        configs.push_back({"", "", o.device, base, {}});
    } else {
        const Sweep sweep = parseSweep(o.sweep);
        if (sweep.knob->biased && o.reference.empty())
            std::fprintf(stderr,
                         "vkpath: warning: --sweep %s without --reference: the two-seed estimate "
                         "measures noise only, "
                         "not the bias of %s; give a deep reference without it to see it\n",
                         sweep.knob->name, sweep.knob->name);
        for (const std::string& value : sweep.values) {
            Configuration c{
                sweep.knob->name, value, fmt::format("{}={}", sweep.knob->name, value), base, {}};
            sweep.knob->apply(c.settings, value);
            configs.push_back(c);
        }
    }
    if (o.denoise) {
        if (o.reference.empty())
            throw InputError(
                "converge --denoise needs --reference: the two-seed estimate measures noise, "
                "not the error a denoiser trades it for");
        image::loadDenoiser();
    }
    std::optional<image::Image> reference;
    if (!o.reference.empty()) {
        reference = image::readImage(o.reference);
        if (reference->width != base.width || reference->height != base.height)
            throw InputError(fmt::format("{}: the reference is {}x{}, the render {}x{} (-d)",
                                         o.reference, reference->width, reference->height,
                                         base.width, base.height));
    }
    const scene::Scene scene = loadRenderScene(o);

    const bool trimmed = o.metric == "trimmed-relmse";
    const char* metric = trimmed ? "trimmed relMSE" : "relMSE";
    auto run = [&](const auto& measureOne) {
        for (Configuration& c : configs) c.curve = measureOne(c);
        writeCsv(o.csv, configs, reference ? "reference" : "two-seed estimate");
        const std::vector<Configuration> shown = tabulated(configs, trimmed);
        plot::Chart chart;
        chart.title = fmt::format(
            "{} {}x{} on {}{}, error against {}",
            std::filesystem::path(o.scene).filename().string(), base.width, base.height, o.device,
            o.denoise ? ", denoised" : "",
            reference ? std::filesystem::path(o.reference).filename().string() : "a second seed");
        chart.xLabel = "wall time (s)";
        chart.yLabel = metric;
        chart.scoreLabel = trimmed ? "efficiency 1/(s*trimmed relMSE)" : "efficiency 1/(s*relMSE)";
        for (const Configuration& c : shown) {
            plot::Series s{c.label, {}, {}};
            for (const Checkpoint& p : c.curve) {
                s.x.push_back(p.wallSeconds);
                s.y.push_back(p.relMse);
            }
            chart.series.push_back(s);
            chart.scores.push_back(efficiency(c.curve));
        }
        ensureParent(o.plot);
        image::writePng(o.plot, plot::renderChart(chart));
        printTables(shown, metric);
        std::printf("%s\n%s\n", o.csv.c_str(), o.plot.c_str());
        return 0;
    };

    if (o.device == "cpu") {
        auto make = [&](const wavefront::RenderSettings& s) {
            return std::make_unique<reference::ReferenceRenderer>(scene, s);
        };
        return run([&](const Configuration& c) {
            return measure<reference::ReferenceRenderer>(
                make, c, spp, reference, false, &c == &configs.front(), o.targetError, o.denoise);
        });
    }
    return withContext(global, [&](vk::Context& context) {
        admitRenderOnDevice(o, scene, context.info());
        auto make = [&](const wavefront::RenderSettings& s) {
            return std::make_unique<wavefront::GpuRenderer>(context, scene, s);
        };
        return run([&](const Configuration& c) {
            return measure<wavefront::GpuRenderer>(
                make, c, spp, reference, true, &c == &configs.front(), o.targetError, o.denoise);
        });
    });
}

}  // namespace

void addConvergeCommand(CLI::App& app, const GlobalOptions& global, Commands& commands) {
    auto o = std::make_shared<ConvergeOptions>();
    auto* cmd = app.add_subcommand(
        "converge", "Error against time: a progressive render measured at each sample count");
    addRenderOptions(*cmd, *o);
    cmd->add_option("--spp", o->spp, "Sample counts to measure at, increasing: 1,2,4,...")
        ->check(parsedBy("N1,N2,...", [](const std::string& text) { parseSppList(text); }))
        ->capture_default_str();
    cmd->add_option("--reference", o->reference,
                    "Reference image (EXR) of the same size; without one the error is estimated "
                    "from a second seed")
        ->check(CLI::ExistingFile);
    cmd->add_flag("--denoise", o->denoise,
                  "Denoise each checkpoint's image (Intel Open Image Denoise 2, as render "
                  "--denoise: guided by the albedo and normal AOVs) before measuring it, its "
                  "time counted; needs --reference");
    std::string knobNames;
    for (const Knob& k : knobs())
        knobNames += (knobNames.empty() ? "" : ", ") + std::string(k.name);
    cmd->add_option("--sweep", o->sweep, "KNOB=v1,v2,...: one curve per value; knobs: " + knobNames)
        ->check(parsedBy("KNOB=v1,v2,...", [](const std::string& text) { parseSweep(text); }));
    cmd->add_option("--csv", o->csv, "Measurements, one row per configuration and sample count")
        ->capture_default_str();
    cmd->add_option("--plot", o->plot, "Log-log plot of relMSE against wall time (PNG)")
        ->capture_default_str();
    cmd->add_option("--metric", o->metric,
                    "The error of the tables and the plot: relmse, or trimmed-relmse (without the "
                    "0.1% of pixels with "
                    "the largest error: robust to fireflies; the CSV has both)")
        ->check(CLI::IsMember({"relmse", "trimmed-relmse"}))
        ->capture_default_str();
    cmd->callback([&global, &commands, o] {
        commands.run = [&global, o] { return runConverge(global, *o); };
    });
}

}  // namespace vkpath::app
