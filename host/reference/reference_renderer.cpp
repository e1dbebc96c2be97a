#include "reference/reference_renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

#include "input_error.h"
#include "scene/camera.h"
#include "wavefront/kernel_features.h"
#include "wavefront/sample_schedule.h"

namespace vkpath::reference {
namespace {

using Clock = std::chrono::steady_clock;

// Paths per pass over the image (whole samples, at least one): the grain of
// progress reports and of the time budget, a fraction of a second of work
// per core.
constexpr uint64_t PATHS_PER_PASS = uint64_t(1) << 18;

wavefront::SceneTables withSettings(wavefront::SceneTables tables,
                                    const wavefront::RenderSettings& settings) {
    tables.info = wavefront::renderSceneInfo(tables, settings);
    return tables;
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
// Whether every component of both (finite) sums still fits a float.
bool fitFloat(const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 m = glm::max(glm::abs(a), glm::abs(b));
    return std::max(std::max(m.x, m.y), m.z) <= FLT_MAX;
}

// Per pixel and channel: the sum of the samples and of their squares.
struct PixelSums {
    glm::dvec3 sum{0.0};
    glm::dvec3 sumSquares{0.0};
};

struct SampleCounts {
    uint64_t dropped = 0;
    uint64_t fireflies = 0;
};

// accumulate.comp's rules for one path sample, with double sums: a NaN or
// infinite sample is dropped; one whose largest component exceeds the
// firefly threshold is counted (and, with a clamp, scaled down to it); one
// that would overflow the GPU's float sums is dropped too, so both
// renderers keep and drop the same samples. `oddSum`: with two sample
// streams, the pixel's sum of its odd-indexed samples (the sample's stream
// is its index's parity), else null.
void accumulate(PixelSums& pixel, glm::dvec3* oddSum, glm::vec3 l, const shared::SceneInfo& info,
                SampleCounts& counts, uint64_t sampleIndex) {
    if (!finite(l)) {
        ++counts.dropped;
        return;
    }
    const float largest = std::max(std::max(l.x, l.y), l.z);
    if (largest > info.fireflyThreshold) ++counts.fireflies;
    if (info.clampRadiance > 0.0f && largest > info.clampRadiance)
        l *= info.clampRadiance / largest;
    const glm::dvec3 d(l);
    const PixelSums next{pixel.sum + d, pixel.sumSquares + d * d};
    if (!finite(l * l) || !fitFloat(next.sum, next.sumSquares)) {
        ++counts.dropped;
        return;
    }
    pixel = next;
    if (oddSum && (sampleIndex & 1) == 1) *oddSum += d;
}

}  // namespace

ReferenceRenderer::ReferenceRenderer(const scene::Scene& scene,
                                     const wavefront::RenderSettings& settings)
    : ReferenceRenderer(wavefront::buildSceneTables(scene), settings) {}

ReferenceRenderer::ReferenceRenderer(wavefront::SceneTables tables,
                                     const wavefront::RenderSettings& settings)
    : m_settings(settings),
      m_tables(withSettings(std::move(tables), settings)),
      m_camera(scene::makeGpuCamera(m_tables.camera, settings.width, settings.height)),
      m_features(wavefront::renderFeatures(m_tables, m_tables.info)),
      m_sampler(makePathSampler(m_tables, m_tables.info, m_features, settings.specialize)) {}

uint32_t ReferenceRenderer::threads() const {
    if (m_settings.threads > 0) return m_settings.threads;
    return std::max(1u, std::thread::hardware_concurrency());
}

std::string ReferenceRenderer::describe() const {
    constexpr uint64_t defined = VKP_FEATURE_BIT(VKP_FEATURE_COUNT) - 1;
    std::string build;
    if (m_sampler->features() != VKP_FEATURES_ALL)
        build =
            fmt::format("the integrator built for the '{}' profile (without {})", m_sampler->name(),
                        wavefront::describeFeatures(defined & ~m_sampler->features()));
    else if (!m_settings.specialize)
        build = "the integrator's general build (--no-specialize)";
    else
        build = "the integrator's general build (no profile holds all of the render's features)";
    return fmt::format("CPU reference: {} threads, {}; the render's features: {}", threads(), build,
                       wavefront::describeFeatures(m_features));
}

glm::vec3 ReferenceRenderer::tracePath(uint32_t pixel, uint32_t sampleIndex,
                                       wavefront::RayCounts& rays,
                                       uint64_t& rejectedLightSamples) const {
    shared::PathAov aov;
    return tracePath(pixel, sampleIndex, rays, rejectedLightSamples, aov);
}

glm::vec3 ReferenceRenderer::tracePath(uint32_t pixel, uint32_t sampleIndex,
                                       wavefront::RayCounts& rays, uint64_t& rejectedLightSamples,
                                       shared::PathAov& aov) const {
    // The loop the GPU runs (shared/integrator.h), one path at a time.
    shared::PathTally tally{};
    const glm::vec3 radiance = m_sampler->tracePath(m_camera, pixel, sampleIndex, tally, aov);
    rays.closest += tally.closestRays;
    rays.shadow += tally.shadowRays;
    rejectedLightSamples += tally.rejectedLightSamples;
    return radiance;
}

wavefront::RenderResult ReferenceRenderer::render(
    const std::function<void(const wavefront::RenderProgress&)>& progress) const {
    return render(wavefront::SampleRange{0, m_settings.samplesPerPixel}, progress);
}

wavefront::RenderResult ReferenceRenderer::render(
    const wavefront::SampleRange& samples,
    const std::function<void(const wavefront::RenderProgress&)>& progress) const {
    return render(samples, wavefront::RenderControl{.progress = progress});
}

wavefront::RenderResult ReferenceRenderer::render(const wavefront::SampleRange& samples,
                                                  const wavefront::RenderControl& control) const {
    const wavefront::RenderSettings& s = m_settings;
    if (uint64_t(samples.first) + samples.count > (uint64_t(1) << 32))
        throw std::out_of_range("sample indices beyond 32 bits");
    const uint32_t width = m_camera.width, height = m_camera.height;
    const uint64_t pixels = uint64_t(width) * height;
    const uint32_t workers = uint32_t(std::min<uint64_t>(threads(), std::max<uint64_t>(height, 1)));

    const shared::SceneInfo& info = m_tables.info;
    std::vector<PixelSums> film(pixels);
    // With two sample streams the film's state is followed by each pixel's
    // odd-stream sum.
    std::vector<glm::dvec3> oddSums(info.sampleStreams == 2 ? pixels : 0, glm::dvec3(0.0));
    // The AOVs' sums (not part of the state: a resumed render's are its own samples').
    std::vector<shared::FilmAovPixel> aovSums(info.aovs != 0 ? pixels : 0, shared::FilmAovPixel{});
    const size_t filmBytes = film.size() * sizeof(PixelSums);
    const size_t oddBytes = oddSums.size() * sizeof(glm::dvec3);
    const wavefront::RenderState before = wavefront::resumedState(
        control, wavefront::CPU_FILM_FORMAT, width, height, samples, filmBytes + oddBytes);
    if (control.resume) {
        std::memcpy(film.data(), control.resume->film.data(), filmBytes);
        std::memcpy(oddSums.data(), control.resume->film.data() + filmBytes, oddBytes);
    }
    std::atomic<uint64_t> nonFinite{0}, fireflies{0}, closestRays{0}, shadowRays{0},
        rejectedLightSamples{0};

    wavefront::RenderResult result;
    result.priorSeconds = before.seconds;
    wavefront::SampleSchedule schedule(s, samples, before, pixels);
    auto statistics = [&] {
        std::vector<wavefront::PixelStatistics> stats(pixels);
        for (size_t i = 0; i < pixels; ++i) {
            for (int c = 0; c < 3; ++c) {
                const wavefront::PixelEstimate e = wavefront::estimatePixel(
                    film[i].sum[c], film[i].sumSquares[c], schedule.samplesOf(i));
                stats[i].mean[c] = e.mean;
                stats[i].varianceOfMean[c] = e.varianceOfMean;
            }
            if (!oddSums.empty())
                stats[i].streamVarianceOfMean = wavefront::streamVarianceOfMean(
                    film[i].sum, oddSums[i], samples.first, schedule.samplesOf(i));
        }
        return stats;
    };
    auto state = [&](double seconds) {
        std::vector<std::byte> bytes(filmBytes + oddBytes);
        std::memcpy(bytes.data(), film.data(), filmBytes);
        std::memcpy(bytes.data() + filmBytes, oddSums.data(), oddBytes);
        const wavefront::RunTally run{
            nonFinite,    fireflies, rejectedLightSamples, {closestRays, shadowRays},
            result.waves, seconds};
        wavefront::RenderState now = wavefront::continuedState(before, std::move(bytes), run);
        schedule.store(now);
        return now;
    };
    const auto start = Clock::now();
    wavefront::WholeSampleGate gate(control, s.timeBudgetSeconds);
    bool ended = false;
    while (!ended) {
        const std::optional<wavefront::SamplePass> pass = schedule.next(statistics);
        if (!pass) break;
        // The pass's pixels as entries: every pixel (threads take rows) or its list.
        const uint64_t entries = pass->pixels.empty() ? pixels : pass->pixels.size();
        const uint64_t block = pass->pixels.empty() ? width : 64;
        uint32_t rounds = pass->rounds;
        while (rounds > 0 && !ended) {
            // Whole rounds, a fraction of a second of work per core.
            const uint32_t chunk = uint32_t(
                std::clamp<uint64_t>(PATHS_PER_PASS / std::max<uint64_t>(entries, 1), 1, rounds));
            std::atomic<uint64_t> nextBlock{0};
            auto work = [&] {
                SampleCounts counts;
                wavefront::RayCounts rays;
                uint64_t rejected = 0;
                for (uint64_t b = nextBlock++; b * block < entries; b = nextBlock++)
                    for (uint64_t e = b * block; e < std::min(entries, (b + 1) * block); ++e) {
                        const uint32_t pixel = pass->pixels.empty() ? uint32_t(e) : pass->pixels[e];
                        // 64-bit: the range may end at 2^32 itself.
                        const uint64_t first = uint64_t(samples.first) + schedule.samplesOf(pixel);
                        for (uint64_t sample = first; sample < first + chunk; ++sample) {
                            shared::PathAov aov;
                            const glm::vec3 l =
                                tracePath(pixel, uint32_t(sample), rays, rejected, aov);
                            if (!aovSums.empty()) {  // accumulate.comp's order and floats
                                shared::FilmAovPixel& a = aovSums[pixel];
                                a.albedo += aov.albedo;
                                a.normal += aov.normal;
                                a.samples += 1;
                            }
                            accumulate(film[pixel], oddSums.empty() ? nullptr : &oddSums[pixel], l,
                                       info, counts, sample);
                        }
                    }
                rejectedLightSamples += rejected;
                nonFinite += counts.dropped;
                fireflies += counts.fireflies;
                closestRays += rays.closest;
                shadowRays += rays.shadow;
            };
            std::vector<std::thread> pool;
            for (uint32_t t = 1; t < workers; ++t) pool.emplace_back(work);
            work();
            for (std::thread& thread : pool) thread.join();

            for (uint32_t r = 0; r < chunk; ++r) schedule.roundDone();
            rounds -= chunk;
            result.paths += entries * chunk;
            result.pathsInFlight = std::max(
                result.pathsInFlight, uint32_t(std::min<uint64_t>(entries * chunk, UINT32_MAX)));
            ++result.waves;
            const uint32_t done = schedule.wholeSamples();
            const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
            if (control.progress)
                control.progress(
                    {done, samples.count, seconds, schedule.lastEstimate(), result.paths});
            if (gate.ends(done, samples.count, seconds, result.stopped))
                ended = true;
            else if (gate.checkpointDue(done, samples.count)) {
                control.checkpoint(state(seconds));
                gate.checkpointed();
            }
            if (!ended)
                gate.previewIfDue(done, samples.count, [&] {
                    return wavefront::meanImage(statistics(), s.width, s.height);
                });
        }
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.rays = {closestRays, shadowRays};
    const wavefront::RenderState end = state(result.seconds);
    result.takeTotals(end);
    result.reachedTarget = schedule.reachedTarget();
    if (control.checkpoint) control.checkpoint(end);

    wavefront::takeImage(statistics(), s.width, s.height, result);
    if (!aovSums.empty()) wavefront::takeAovs(aovSums, s.width, s.height, result);
    return result;
}

}  // namespace vkpath::reference
