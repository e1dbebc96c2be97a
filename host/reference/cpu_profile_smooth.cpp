// The CPU reference's integrator compiled for VKP_FEATURE_PROFILE_SMOOTH
// (shared/feature_profiles.h). The define comes before every include.
#define VKP_CPU_FEATURES VKP_FEATURE_PROFILE_SMOOTH
#include "reference/path_sampler_of.h"

namespace vkpath::reference {

template <>
std::unique_ptr<PathSampler> makeProfilePathSampler<VKP_CPU_FEATURES>(
    const char* name, const wavefront::SceneTables& tables, const shared::SceneInfo& info) {
    return std::make_unique<PathSamplerOf<VKP_CPU_FEATURES>>(name, tables, info);
}

}  // namespace vkpath::reference
