// The CPU reference path tracer: the wavefront renderer's estimator written
// as a plain loop over each path's bounces, with the kernels' own math
// (shaders/shared/path_tracer.h through PathTracerView, compiled for the
// scene's features: reference/path_sampler.h) and the same random
// numbers (key (pixel, sampleIndex, seed), the same dimension per decision).
// With the same seed both renderers follow the same paths, so the difference
// of their images measures the wavefront machinery (queues, compaction,
// accumulation) and float rounding, not noise.
//
// Per path, in shade.comp's order: camera ray; then per bounce the closest
// hit, emission (or the environment on a miss) with its MIS weight, a stop at
// maxDepth, lightSamples light samples each tested by an any-hit shadow ray
// (the unoccluded ones summed, then added), and the BSDF sample with Russian
// roulette. Each path sample then meets accumulate.comp's rules: NaN,
// infinite or float-overflowing samples are dropped and counted, fireflies
// counted (and clamped if asked); pixel sums are kept in double. The AOVs'
// sums (RenderSettings::surfaceAovs) are floats added in sample order, as
// accumulate.comp adds them.
//
// Threads take rows of the image; a pixel's samples are always added in
// sample order, so the image is the same bit for bit for any thread count.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "reference/path_sampler.h"
#include "scene/scene.h"
#include "shared/camera.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/render_types.h"

namespace vkpath::reference {

class ReferenceRenderer {
  public:
    // Builds the scene tables as the GPU renderer does (buildSceneTables).
    ReferenceRenderer(const scene::Scene& scene, const wavefront::RenderSettings& settings);
    // From tables the caller built, and may have changed: tests render with a
    // deliberately wrong table to show that a comparison catches it. The
    // camera is the tables' (render space).
    ReferenceRenderer(wavefront::SceneTables tables, const wavefront::RenderSettings& settings);

    ReferenceRenderer(const ReferenceRenderer&) = delete;
    ReferenceRenderer& operator=(const ReferenceRenderer&) = delete;

    // Renders settings.samplesPerPixel samples per pixel (fewer when the
    // time budget runs out: it is checked after each pass of whole samples).
    wavefront::RenderResult render(
        const std::function<void(const wavefront::RenderProgress&)>& progress = {}) const;
    // The given samples of every pixel (the time budget as above); the result holds their mean.
    wavefront::RenderResult render(
        const wavefront::SampleRange& samples,
        const std::function<void(const wavefront::RenderProgress&)>& progress = {}) const;
    // The same with stops, checkpoints and resuming (wavefront::RenderControl);
    // throws InputError for a state it cannot continue.
    wavefront::RenderResult render(const wavefront::SampleRange& samples,
                                   const wavefront::RenderControl& control) const;

    // The radiance one path brings to its pixel: path `sampleIndex` of pixel
    // y * width + x, exactly what the wavefront renderer accumulates for it.
    // Adds the rays it traces to `rays` and its light samples of pdf 0 to
    // `rejectedLightSamples`.
    glm::vec3 tracePath(uint32_t pixel, uint32_t sampleIndex, wavefront::RayCounts& rays,
                        uint64_t& rejectedLightSamples) const;
    // The same, with the path's AOVs in `aov` (set in renders with
    // RenderSettings::surfaceAovs).
    glm::vec3 tracePath(uint32_t pixel, uint32_t sampleIndex, wavefront::RayCounts& rays,
                        uint64_t& rejectedLightSamples, shared::PathAov& aov) const;

    const wavefront::SceneTables& tables() const { return m_tables; }
    // Worker threads render() uses.
    uint32_t threads() const;
    // The integrator's build it runs: "general" (settings.specialize false, or
    // no profile covers the scene) or a profile of shared/feature_profiles.h.
    const PathSampler& sampler() const { return *m_sampler; }
    // The render's features (wavefront::renderFeatures).
    uint64_t features() const { return m_features; }
    // One line for a user: the threads, the build and the scene's features.
    std::string describe() const;

  private:
    wavefront::RenderSettings m_settings;
    wavefront::SceneTables m_tables;
    shared::Camera m_camera;
    uint64_t m_features;
    std::unique_ptr<const PathSampler> m_sampler;  // reads m_tables: declared after it
};

}  // namespace vkpath::reference
