#include "app/auto_search.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "image/metrics.h"

namespace vkpath::app {

PilotMeasurement measurePair(const image::Image& a, const image::Image& b, double secondsA,
                             double secondsB) {
    double sum = 0, sumSquares = 0;
    uint64_t pixels = 0;
    for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i) {
        double term = 0;
        bool finite = true;
        for (int c = 0; c < 3; ++c) {
            const double x = a.pixels[i][c], y = b.pixels[i][c];
            finite = finite && std::isfinite(x) && std::isfinite(y);
            const double m = (x + y) / 2;
            term += (x - y) * (x - y) / 2 / (m * m + image::RELMSE_EPSILON);
        }
        if (!finite) continue;
        term /= 3;
        sum += term;
        sumSquares += term * term;
        ++pixels;
    }
    PilotMeasurement m;
    m.seconds = (secondsA + secondsB) / 2;
    if (pixels == 0) return m;
    m.relMse = sum / double(pixels);
    const double variance =
        pixels > 1 ? std::max(0.0, (sumSquares - sum * m.relMse) / double(pixels - 1)) : 0.0;
    m.relMseStdError = std::sqrt(variance / double(pixels));
    return m;
}

double efficiency(const PilotMeasurement& m) {
    const double cost = m.seconds * m.relMse;
    return cost > 0 ? 1 / cost : std::numeric_limits<double>::infinity();
}

namespace {

// The relative standard deviation of a measurement's efficiency: its error
// estimate's and its time's (a mean of two renders).
double relativeNoise(const PilotMeasurement& m) {
    const double error = m.relMse > 0 ? m.relMseStdError / m.relMse : 1.0;
    return std::sqrt(error * error + PILOT_TIME_NOISE * PILOT_TIME_NOISE / 2);
}

}  // namespace

bool clearlyMoreEfficient(const PilotMeasurement& candidate, const PilotMeasurement& incumbent) {
    if (candidate.relMse <= 0 || incumbent.relMse <= 0) return false;  // nothing measured
    const double logRatio = std::log(efficiency(candidate) / efficiency(incumbent));
    return logRatio >
           EVIDENCE_SIGMAS * std::hypot(relativeNoise(candidate), relativeNoise(incumbent));
}

bool clearlyFaster(double candidateSeconds, double incumbentSeconds) {
    if (candidateSeconds <= 0 || incumbentSeconds <= 0) return false;
    return std::log(incumbentSeconds / candidateSeconds) >
           EVIDENCE_SIGMAS * std::sqrt(2.0) * PILOT_TIME_NOISE;
}

namespace {

using wavefront::KernelForm;
using wavefront::RenderSettings;
using wavefront::SamplerKind;

// What the pilots spend of the render's budget.
constexpr double BUDGET_SHARE = 0.05;
// Fewer paths than this per pilot render measure noise, not settings.
constexpr double FEWEST_PILOT_PATHS = 2048;
// The calibration pilot: at most this many pixels, as many samples as make
// CALIBRATION_PATHS paths, several times what a render spends besides its
// paths (about 10^4 paths' worth on lavapipe).
constexpr uint64_t CALIBRATION_PIXELS = 4096;
constexpr double CALIBRATION_PATHS = 65536;
// ... and at most this share of the render's paths (-s) or time budget.
constexpr double CALIBRATION_SHARE = 0.01;
// A render whose 5% holds fewer paths than this (the incumbent's pair and a
// few comparisons of FEWEST_PILOT_PATHS) is not measured at all.
constexpr double FEWEST_RENDER_SHARE_PATHS = 8 * 2 * FEWEST_PILOT_PATHS;
// Pixels a comparison pilot has before its spp grow (Search::run, step 3).
constexpr uint64_t PILOT_PIXELS = 1024;
// The variance knobs in the order they are searched, with the pilot pairs
// each is planned to take, in the incumbent's pairs' cost (light samples: 4
// per vertex, about 2.5 times a path with one, then 8 or 2).
constexpr std::pair<const char*, int> VARIANCE_KNOBS[] = {{"sampler", 1},
                                                          {"light-sampler", 1},
                                                          {"light-samples", 4},
                                                          {"guide-spheres", 2},
                                                          {"rr-depth", 2}};

// A pilot seed: a hash of the render's seed and the pilot's number, never the
// render's seed itself.
uint32_t pilotSeed(uint32_t seed, uint32_t pilot) {
    uint32_t x = seed * 0x9E3779B9u + pilot * 0x85EBCA6Bu + 0x632BE5ABu;
    x ^= x >> 16;
    x *= 0x7FEB352Du;
    x ^= x >> 15;
    x *= 0x846CA68Bu;
    x ^= x >> 16;
    return x == seed ? x + 1 : x;
}

// The largest power of two at most `x` (at least 1), capped at `most`.
uint32_t powerOfTwoBelow(double x, uint32_t most) {
    uint32_t p = 1;
    while (p * 2 <= x && p * 2 <= most) p *= 2;
    return p;
}

struct Knobs {
    uint32_t rouletteDepth;
    uint32_t lightSamples;
    SamplerKind sampler;
    wavefront::LightSampling lightSampling;
    float guide;
    KernelForm form;
    uint32_t paths;
};

struct Film {
    uint32_t width = 1, height = 1;
    uint64_t pixels() const { return uint64_t(width) * height; }
};

// About `pixels` pixels of the film's aspect ratio (the whole film at most).
Film filmOf(double pixels, uint32_t width, uint32_t height) {
    const double full = double(width) * height;
    if (pixels >= full) return {width, height};
    const double scale = std::sqrt(std::max(pixels, 1.0) / full);
    return {std::max(1u, uint32_t(std::lround(width * scale))),
            std::max(1u, uint32_t(std::lround(height * scale)))};
}

class Search {
  public:
    Search(const AutoRequest& request, const PilotRenderer& render)
        : m_request(request), m_render(render) {}

    AutoChoice run();

  private:
    RenderSettings settingsOf(const Knobs& k, Film film, uint32_t spp, uint32_t seed) const {
        RenderSettings s = m_request.base;
        s.width = film.width;
        s.height = film.height;
        s.samplesPerPixel = spp;
        s.seed = seed;
        s.rouletteDepth = k.rouletteDepth;
        s.lightSamples = k.lightSamples;
        s.sampler = k.sampler;
        s.lightSampling = k.lightSampling;
        s.guideFraction = k.guide;
        if (m_request.gpu) {
            s.kernel = k.form;
            s.maxPathsInFlight = k.paths;
        }
        s.timeBudgetSeconds.reset();
        s.targetError.reset();
        s.adaptive = false;  // pilots sample uniformly
        return s;
    }
    PilotRender pilot(const RenderSettings& s) {
        PilotRender r = m_render(s);
        m_spent += r.seconds;
        m_setup += r.setupSeconds;
        ++m_renders;
        return r;
    }
    PilotMeasurement measure(const Knobs& k) {
        const PilotRender a =
            pilot(settingsOf(k, m_film, m_spp, pilotSeed(m_request.base.seed, 1)));
        const PilotRender b =
            pilot(settingsOf(k, m_film, m_spp, pilotSeed(m_request.base.seed, 2)));
        m_measuredWall = (a.seconds + b.seconds) / 2;
        return measurePair(a.image, b.image, a.costSeconds, b.costSeconds);
    }
    // The incumbent and the wall seconds of one of its pilots (what the next
    // pilots' cost is predicted from).
    void setIncumbent(const PilotMeasurement& m, double wallSeconds) {
        m_incumbent = m;
        m_incumbentWall = wallSeconds;
    }
    double pilotSeconds() const { return m_incumbentWall; }
    // The wall seconds of one pilot of a candidate whose paths cost
    // `costFactor` times the incumbent's: what a render costs besides its
    // paths (m_overhead) does not grow with them.
    double candidateSeconds(double costFactor) const {
        return m_overhead + std::max(m_incumbentWall - m_overhead, 0.0) * costFactor;
    }
    // The pilot pairs planned from `knob` on (VARIANCE_KNOBS' counts).
    int comparisonsFrom(const char* knob) const {
        int count = 0;
        bool from = false;
        for (const auto& [name, candidates] : VARIANCE_KNOBS) {
            from = from || std::string(name) == knob;
            if (from && searched(name)) count += candidates;
        }
        return count;
    }
    // Shrinks the pilots' film (never their spp) so that the comparisons
    // planned from `knob` on, and the incumbent's again on the smaller film
    // (a pixel's error grows with its footprint: only pilots of one film
    // compare), fit what is left of the budget at the incumbent's cost per
    // pixel (more light samples cost more); false when they would fall under
    // FEWEST_PILOT_PATHS.
    bool replan(const char* knob) {
        const int comparisons = comparisonsFrom(knob);
        if (comparisons == 0 || affordable(2 * comparisons * pilotSeconds())) return true;
        const double perRender = (m_budget - m_spent) / (2.0 * (comparisons + 1)) - m_overhead;
        const double pixels =
            perRender / std::max(m_incumbentWall - m_overhead, 1e-9) * double(m_film.pixels());
        if (pixels * m_spp < FEWEST_PILOT_PATHS) return false;
        m_film = filmOf(pixels, m_request.base.width, m_request.base.height);
        const PilotMeasurement m = measure(m_best);
        setIncumbent(m, m_measuredWall);
        return true;
    }
    // Whether `seconds` more of pilots stay within the budget.
    bool affordable(double seconds) const { return m_spent + seconds <= m_budget; }
    // One render of `spp` samples over `pixels` pixels at the calibrated speed.
    double predictedSeconds(double pixels, double spp) const {
        const double paths = pixels * spp;
        return paths * m_secondsPerPath +
               std::ceil(paths / double(m_best.paths ? m_best.paths : 1u << 20)) * m_overhead;
    }
    void setSource(const char* knob, KnobSource source) {
        for (auto& [name, s] : m_choice.sources)
            if (name == knob) s = source;
    }
    KnobSource sourceOf(const char* knob) const {
        for (const auto& [name, s] : m_choice.sources)
            if (name == knob) return s;
        return KnobSource::DoesNotApply;
    }
    bool searched(const char* knob) const { return sourceOf(knob) == KnobSource::NotMeasured; }

    // Coordinate descent over one variance knob: each candidate in order
    // (`apply` makes candidate i from the incumbent so far, or says it is the
    // incumbent's render), measured against the incumbent, which it replaces
    // when it clearly wins; the search ends where the budget does. False when
    // it ran out.
    template <typename Apply>
    bool descend(const char* knob, size_t candidates, const Apply& apply);
    bool chooseKernelForm();
    bool choosePathsInFlight();
    AutoChoice finish(std::string skipped);

    const AutoRequest& m_request;
    const PilotRenderer& m_render;
    AutoChoice m_choice;
    Knobs m_best{};
    PilotMeasurement m_incumbent;  // cost seconds (PilotRender::costSeconds) and error
    double m_incumbentWall = 0;    // wall seconds of one of its pilots
    double m_measuredWall = 0;     // of the last pair measured
    Film m_film;
    uint32_t m_spp = 1;
    double m_budget = std::numeric_limits<double>::infinity();
    double m_spent = 0, m_setup = 0;
    uint32_t m_renders = 0;
    double m_overhead = 0;        // seconds of a render besides its paths (one wave)
    double m_secondsPerPath = 0;  // the default settings' (calibration)
};

template <typename Apply>
bool Search::descend(const char* knob, size_t candidates, const Apply& apply) {
    if (!searched(knob)) return true;
    if (!replan(knob)) return false;
    bool measured = false;
    for (size_t i = 0; i < candidates; ++i) {
        Knobs k = m_best;
        double costFactor = 1;
        if (!apply(i, k, costFactor)) continue;  // the same render as the incumbent
        if (!affordable(2 * candidateSeconds(costFactor))) {
            if (measured) setSource(knob, KnobSource::Measured);
            return false;
        }
        const PilotMeasurement m = measure(k);
        measured = true;
        if (clearlyMoreEfficient(m, m_incumbent)) {
            m_best = k;
            setIncumbent(m, m_measuredWall);
        }
    }
    setSource(knob, measured ? KnobSource::Measured : KnobSource::DoesNotApply);
    return true;
}

bool Search::chooseKernelForm() {
    if (!searched("kernel")) return true;
    Knobs k = m_best;
    k.form = m_best.form == KernelForm::Megakernel ? KernelForm::Wavefront : KernelForm::Megakernel;
    if (!affordable(1.5 * pilotSeconds())) return false;
    const PilotRender r = pilot(settingsOf(k, m_film, m_spp, pilotSeed(m_request.base.seed, 1)));
    setSource("kernel", KnobSource::Measured);
    if (clearlyFaster(r.costSeconds, m_incumbent.seconds)) {
        m_best.form = k.form;
        m_incumbent.seconds = r.costSeconds;  // the same image: the same error
        m_incumbentWall = r.seconds;
    }
    return true;
}

bool Search::choosePathsInFlight() {
    if (!searched("paths-in-flight")) return true;
    // Measured on the whole film (a wave's size is paths, not pixels), over
    // enough samples for two waves of the larger candidate; only a candidate
    // that changes the render's waves is a candidate.
    const RenderSettings& base = m_request.base;
    const double pixels = double(base.width) * base.height;
    const double renderPaths =
        m_request.spp ? pixels * *m_request.spp : m_budget / BUDGET_SHARE / m_secondsPerPath;
    bool measured = false;
    for (const uint32_t candidate : {m_best.paths * 4, m_best.paths / 4}) {
        if (candidate < 1024 || renderPaths <= std::min(candidate, m_best.paths)) continue;
        const uint32_t spp = uint32_t(std::ceil(2.0 * std::max(candidate, m_best.paths) / pixels));
        if (!affordable(2 * predictedSeconds(pixels, spp))) {
            if (measured) setSource("paths-in-flight", KnobSource::Measured);
            return false;
        }
        Knobs k = m_best;
        k.paths = candidate;
        const Film whole{base.width, base.height};
        const uint32_t seed = pilotSeed(base.seed, 1);
        const double incumbent = pilot(settingsOf(m_best, whole, spp, seed)).costSeconds;
        const double seconds = pilot(settingsOf(k, whole, spp, seed)).costSeconds;
        measured = true;
        if (clearlyFaster(seconds, incumbent)) m_best.paths = candidate;
    }
    setSource("paths-in-flight", measured ? KnobSource::Measured : KnobSource::DoesNotApply);
    return true;
}

AutoChoice Search::finish(std::string skipped) {
    m_choice.rouletteDepth = m_best.rouletteDepth;
    m_choice.lightSamples = m_best.lightSamples;
    m_choice.sampler = m_best.sampler == SamplerKind::Sobol ? "sobol" : "independent";
    m_choice.guideSpheres = m_best.guide;
    m_choice.lightSampler = wavefront::lightSamplingName(m_best.lightSampling);
    if (m_request.gpu) {
        m_choice.kernel = wavefront::kernelFormName(m_best.form);
        m_choice.pathsInFlight = m_best.paths;
    }
    m_choice.pilotSeconds = m_spent;
    m_choice.setupSeconds = m_setup;
    m_choice.budgetSeconds = std::isfinite(m_budget) ? m_budget / BUDGET_SHARE : 0.0;
    m_choice.pilotRenders = m_renders;
    const std::string last = fmt::format("{}x{} at {} spp", m_film.width, m_film.height, m_spp);
    if (!m_choice.pilotFilm.empty() && last != m_choice.pilotFilm)
        m_choice.pilotFilm += ", then " + last;
    m_choice.skipped = std::move(skipped);
    return m_choice;
}

AutoChoice Search::run() {
    const AutoRequest& r = m_request;
    const RenderSettings& base = r.base;
    m_best = {base.rouletteDepth,
              base.lightSamples,
              base.sampler,
              base.lightSampling,
              base.guideFraction,
              base.kernel.value_or(r.defaultForm),
              base.maxPathsInFlight.value_or(r.defaultPathsInFlight)};
    const bool depth = base.maxDepth >= 1;  // light samples and guiding need a bounce
    // Roulette's candidates (from bounce 3, none) differ from the incumbent
    // only where the paths are long enough to meet them.
    const uint32_t noRoulette = base.maxDepth + 1;
    const bool roulette = std::min(3u, noRoulette) != std::min(base.rouletteDepth, noRoulette) ||
                          noRoulette != std::min(base.rouletteDepth, noRoulette);
    auto source = [](bool given, bool applies) {
        return given     ? KnobSource::Given
               : applies ? KnobSource::NotMeasured
                         : KnobSource::DoesNotApply;
    };
    m_choice.sources = {
        {"rr-depth", source(r.givenRouletteDepth, roulette)},
        {"light-samples", source(r.givenLightSamples, depth && r.sceneHasLights)},
        {"sampler", source(r.givenSampler, true)},
        {"light-sampler", source(r.givenLightSampler, depth && r.sceneHasLightTree)},
        {"guide-spheres", source(r.givenGuideSpheres, depth && r.sceneHasGuideSpheres)},
        {"kernel", source(r.givenKernel, r.gpu)},
        {"paths-in-flight", source(r.givenPathsInFlight, r.gpu)},
    };

    // 0. Nothing to search, or a render of fewer paths than pilots need
    // within 5% of it: no pilot.
    if (std::none_of(m_choice.sources.begin(), m_choice.sources.end(),
                     [](const auto& knob) { return knob.second == KnobSource::NotMeasured; }))
        return finish("every knob is given or does not apply here");
    const double fullPixels = double(base.width) * base.height;
    double calibrationPaths = CALIBRATION_PATHS;
    if (r.spp) {
        const double renderPaths = fullPixels * *r.spp;
        if (BUDGET_SHARE * renderPaths < FEWEST_RENDER_SHARE_PATHS)
            return finish(
                fmt::format("{:.3g} paths are too few to measure settings within 5% of "
                            "them: the knobs not given keep their defaults",
                            renderPaths));
        calibrationPaths = std::min(calibrationPaths, CALIBRATION_SHARE * renderPaths);
    }
    // (A time budget's paths are not known before the calibration: its size
    // assumes at least 1.6 Mpaths/s, lavapipe's least on the suite.)
    if (r.timeBudget)
        calibrationPaths = std::min(calibrationPaths, CALIBRATION_SHARE * *r.timeBudget * 1.6e6);

    // 1. What a render costs besides its paths (a film of a few pixels, one
    // sample), and the default settings' time per path (calibration).
    const uint32_t seedA = pilotSeed(base.seed, 1);
    // The least of two: the first render of a process also pays for its start.
    const Film tiny = filmOf(16, base.width, base.height);
    m_overhead = pilot(settingsOf(m_best, tiny, 1, seedA)).seconds;
    m_overhead = std::min(m_overhead, pilot(settingsOf(m_best, tiny, 1, seedA)).seconds);
    const Film calibration =
        filmOf(std::min({fullPixels, double(CALIBRATION_PIXELS), calibrationPaths}), base.width,
               base.height);
    const uint32_t calibrationSpp =
        uint32_t(std::ceil(calibrationPaths / double(calibration.pixels())));
    const double calibrated = pilot(settingsOf(m_best, calibration, calibrationSpp, seedA)).seconds;
    m_secondsPerPath = std::max(calibrated - m_overhead, 0.1 * calibrated) /
                       (double(calibration.pixels()) * calibrationSpp);

    // 2. The budget: the render's time at the default settings for -s, its
    // time budget, whichever is smaller (a target error's: after step 3).
    double renderSeconds = std::numeric_limits<double>::infinity();
    if (r.spp) renderSeconds = predictedSeconds(fullPixels, *r.spp);
    if (r.timeBudget) renderSeconds = std::min(renderSeconds, *r.timeBudget);
    m_budget = BUDGET_SHARE * renderSeconds;

    // 3. The pilots' size: the comparisons planned share what is left, two
    // renders each; pixels up to PILOT_PIXELS, then samples up to 64 (powers
    // of two, where the Sobol' points are nets), then the whole film. Samples
    // before pixels: at a few samples the error of a pixel is its footprint's
    // edges (the Sobol' points stratify them better with every sample), which
    // no knob changes; at more, the light transport the knobs trade (the
    // white-sky box of tests/render/auto_settings_test.cpp: at 2 spp two
    // light samples showed no gain, at 8 they halve the error as at 64).
    int comparisons = 1 + comparisonsFrom("sampler");  // and the incumbent's
    if (searched("kernel")) comparisons += 1;
    const double perRender =
        std::isfinite(m_budget) ? (m_budget - m_spent) / (2.0 * comparisons) : 0.0;
    double paths = std::isfinite(m_budget) ? (perRender - m_overhead) / m_secondsPerPath
                                           : 4.0 * PILOT_PIXELS;  // a target error alone
    if (paths < FEWEST_PILOT_PATHS)
        return finish(
            fmt::format("the render is too short for pilots of {} paths within 5% of it: the knobs "
                        "not given keep their defaults",
                        FEWEST_PILOT_PATHS));
    m_spp = powerOfTwoBelow(paths / double(PILOT_PIXELS), 64);
    m_film = filmOf(paths / m_spp, base.width, base.height);
    if (m_film.pixels() == uint64_t(fullPixels)) m_spp = powerOfTwoBelow(paths / fullPixels, 256);

    // 4. The incumbent: the render's own settings.
    const PilotMeasurement incumbent = measure(m_best);
    setIncumbent(incumbent, m_measuredWall);
    m_choice.pilotFilm = fmt::format("{}x{} at {} spp", m_film.width, m_film.height, m_spp);
    if (r.targetError) {
        // The time the target implies at the default settings: error falls
        // as 1 / spp.
        const double spp = m_spp * m_incumbent.relMse / *r.targetError;
        m_budget = std::min(m_budget, BUDGET_SHARE * predictedSeconds(fullPixels, spp));
    }
    if (m_spent > m_budget)
        return finish(
            "the render is too short to compare settings within 5% of it: the knobs not given keep "
            "their defaults");

    // 5. The knobs, by expected effect (docs/TRADEOFFS.md): the kernel form
    // (time only, one pilot), the sampler, light samples, guiding, roulette.
    bool withinBudget = chooseKernelForm();
    withinBudget = withinBudget && descend("sampler", 1, [&](size_t, Knobs& k, double&) {
                       k.sampler = k.sampler == SamplerKind::Sobol ? SamplerKind::Independent
                                                                   : SamplerKind::Sobol;
                       return true;
                   });
    withinBudget = withinBudget && descend("light-sampler", 1, [&](size_t, Knobs& k, double&) {
                       // The other of what the render's setting resolves to.
                       const bool tree = k.lightSampling == wavefront::LightSampling::Tree ||
                                         (k.lightSampling == wavefront::LightSampling::Auto &&
                                          r.lightTreeByDefault);
                       k.lightSampling =
                           tree ? wavefront::LightSampling::Power : wavefront::LightSampling::Tree;
                       return true;
                   });
    withinBudget =
        withinBudget && descend("light-samples", 2, [&](size_t i, Knobs& k, double& cost) {
            // Four first (the larger step stands further above the pilots'
            // noise), then eight where four won, else two.
            const uint32_t candidate = i == 0 ? 4 : m_best.lightSamples == 4 ? 8 : 2;
            if (candidate == m_best.lightSamples) return false;
            cost = (1.0 + candidate) / (1.0 + m_best.lightSamples);
            k.lightSamples = candidate;
            return true;
        });
    withinBudget = withinBudget && descend("guide-spheres", 2, [&](size_t i, Knobs& k, double&) {
                       const float candidates[] = {0.5f, 0.0f};
                       if (candidates[i] == m_best.guide) return false;
                       k.guide = candidates[i];
                       return true;
                   });
    withinBudget = withinBudget && descend("rr-depth", 2, [&](size_t i, Knobs& k, double&) {
                       // Roulette from bounce 3, and none (past the last bounce): a depth
                       // beyond maxDepth + 1 is the same render as maxDepth + 1.
                       const uint32_t off = base.maxDepth + 1;
                       const uint32_t candidate = i == 0 ? 3 : off;
                       if (std::min(candidate, off) == std::min(m_best.rouletteDepth, off))
                           return false;
                       k.rouletteDepth = candidate;
                       return true;
                   });
    if (withinBudget) choosePathsInFlight();
    std::string notMeasured;
    for (const auto& [name, s] : m_choice.sources)
        if (s == KnobSource::NotMeasured) notMeasured += (notMeasured.empty() ? "" : ", ") + name;
    return finish(
        notMeasured.empty() ? "" : "not within the budget, so at their defaults: " + notMeasured);
}

}  // namespace

AutoChoice chooseSettings(const AutoRequest& request, const PilotRenderer& render) {
    return Search(request, render).run();
}

}  // namespace vkpath::app
