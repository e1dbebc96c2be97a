#include "reference/path_sampler.h"

#include <array>

#include "reference/cpu_profiles.h"
#include "reference/path_sampler_of.h"

namespace vkpath::reference {

// Defined in the profiles' translation units.
std::unique_ptr<PathSampler> makeSmoothPathSampler(const char*, const wavefront::SceneTables&,
                                                   const shared::SceneInfo&);
std::unique_ptr<PathSampler> makeSmoothAovsPathSampler(const char*, const wavefront::SceneTables&,
                                                       const shared::SceneInfo&);
std::unique_ptr<PathSampler> makeCorePathSampler(const char*, const wavefront::SceneTables&,
                                                 const shared::SceneInfo&);

namespace {

const std::array<CpuProfile, 3> PROFILES = {{
    {"smooth", VKP_CPU_PROFILE_SMOOTH, makeSmoothPathSampler},
    {"smooth-aovs", VKP_CPU_PROFILE_SMOOTH_AOVS, makeSmoothAovsPathSampler},
    {"core", VKP_CPU_PROFILE_CORE, makeCorePathSampler},
}};

}  // namespace

std::span<const CpuProfile> cpuProfiles() {
    return PROFILES;
}

std::unique_ptr<PathSampler> makePathSampler(const wavefront::SceneTables& tables,
                                             const shared::SceneInfo& info, uint64_t features,
                                             bool specialize) {
    if (specialize)
        for (const CpuProfile& profile : PROFILES)
            if ((features & ~profile.features) == 0)
                return profile.make(profile.name, tables, info);
    return std::make_unique<PathSamplerOf<VKP_FEATURES_ALL>>("general", tables, info);
}

}  // namespace vkpath::reference
