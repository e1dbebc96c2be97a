#include "reference/path_sampler.h"

#include "reference/path_sampler_of.h"
#include "shared/feature_profiles.h"

namespace vkpath::reference {

#define VKP_DECLARE_PROFILE(NAME, key, label)                                        \
    template <>                                                                      \
    std::unique_ptr<PathSampler> makeProfilePathSampler<VKP_FEATURE_PROFILE_##NAME>( \
        const char*, const wavefront::SceneTables&, const shared::SceneInfo&);
VKP_FEATURE_PROFILES(VKP_DECLARE_PROFILE)
#undef VKP_DECLARE_PROFILE

namespace {

#define VKP_PROFILE_ENTRY(NAME, key, label)       \
    CpuProfile{label, VKP_FEATURE_PROFILE_##NAME, \
               makeProfilePathSampler<VKP_FEATURE_PROFILE_##NAME>},
const CpuProfile PROFILES[] = {VKP_FEATURE_PROFILES(VKP_PROFILE_ENTRY)};
#undef VKP_PROFILE_ENTRY

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
