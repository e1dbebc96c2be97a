// The CPU reference's integrator over one scene: shared/integrator.h
// tracePath from the camera ray of a pixel's sample, compiled for a feature
// set (the general code, or a profile of shared/feature_profiles.h). The
// reference renderer holds one and asks it for every path:
//
//   std::unique_ptr<const PathSampler> s = makePathSampler(tables, info, features, true);
//   glm::vec3 radiance = s->tracePath(camera, pixel, sampleIndex, tally);
//
// Every build gives the same radiance bit for bit: a profile leaves out only
// code that a scene with its features never runs
// (tests/render/all_scenes_test.cpp, TheCpuProfileGivesTheSameImage).
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <memory>
#include <span>

#include "shared/camera.h"
#include "shared/path_state.h"
#include "shared/scene_data.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::reference {

class PathSampler {
  public:
    virtual ~PathSampler() = default;
    // The features its code was compiled for: VKP_FEATURES_ALL for the
    // general build.
    virtual uint64_t features() const = 0;
    // "general" or the profile's name.
    virtual const char* name() const = 0;
    // The radiance of path `sampleIndex` of `pixel` (y * width + x of the
    // camera's image) and its AOVs in `aov` (set only in renders with
    // SceneInfo::aovs); adds its rays to `tally`.
    virtual glm::vec3 tracePath(const shared::Camera& camera, uint32_t pixel, uint32_t sampleIndex,
                                shared::PathTally& tally, shared::PathAov& aov) const = 0;
};

// The build of the profile whose mask is `Features` (shared/feature_profiles.h),
// named `name`: defined in the profile's translation unit, cpu_profile_KEY.cpp.
template <uint64_t Features>
std::unique_ptr<PathSampler> makeProfilePathSampler(const char* name,
                                                    const wavefront::SceneTables& tables,
                                                    const shared::SceneInfo& info);

// A profile's build, named `name` (CpuProfile::name).
using MakePathSampler = std::unique_ptr<PathSampler> (*)(const char* name,
                                                         const wavefront::SceneTables& tables,
                                                         const shared::SceneInfo& info);

struct CpuProfile {
    const char* name;
    uint64_t features;
    MakePathSampler make;
};

// The profiles compiled in, fewest features first.
std::span<const CpuProfile> cpuProfiles();

// The integrator for a render of `tables` with `info` (its SceneInfo) and
// `features` (wavefront::renderFeatures): with `specialize`, the first
// profile whose features hold them all; else, or when none does, the general
// build. `tables` must outlive it.
std::unique_ptr<PathSampler> makePathSampler(const wavefront::SceneTables& tables,
                                             const shared::SceneInfo& info, uint64_t features,
                                             bool specialize);

}  // namespace vkpath::reference
