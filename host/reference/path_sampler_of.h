// PathSampler for the feature set of the translation unit that includes this
// (shared::kernelFeatures): the general build in path_sampler.cpp, a profile
// in each cpu_profile_KEY.cpp (shared/feature_profiles.h). Included by those
// alone: PathSamplerOf<F> must be instantiated only where the shared code is
// compiled for F (PathTracerViewOf asserts it).
#pragma once

#include "reference/path_sampler.h"
#include "reference/path_tracer_view.h"

namespace vkpath::reference {

template <uint64_t Features>
class PathSamplerOf final : public PathSampler {
  public:
    PathSamplerOf(const char* name, const wavefront::SceneTables& tables,
                  const shared::SceneInfo& info)
        : m_name(name), m_view(tables, info) {}

    uint64_t features() const override { return Features; }
    const char* name() const override { return m_name; }

    // The whole path in one function: `flatten` inlines every call in it
    // (the bounce, the traversals, the light and BSDF samples), which GCC
    // left as calls passing structs through memory (docs/BENCHMARKS.md,
    // "What each part of its design buys").
    __attribute__((flatten)) glm::vec3 tracePath(const shared::Camera& camera, uint32_t pixel,
                                                 uint32_t sampleIndex, shared::PathTally& tally,
                                                 shared::PathAov& aov) const override {
        const shared::RngKey key = shared::pathRngKey(m_view.sceneInfo(), pixel, sampleIndex);
        shared::PathState path = shared::startPath(camera, pixel, key);
        m_view.tracePath(path, key, tally);
        aov = path.aov;
        return path.radiance;
    }

  private:
    const char* m_name;
    shared::PathTracerViewOf<Features> m_view;
};

}  // namespace vkpath::reference
