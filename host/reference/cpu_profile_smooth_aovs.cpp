// The CPU reference's integrator compiled for VKP_CPU_PROFILE_SMOOTH_AOVS
// (reference/cpu_profiles.h). The define comes before every include.
#define VKP_CPU_FEATURES VKP_CPU_PROFILE_SMOOTH_AOVS
#include "reference/cpu_profiles.h"
#include "reference/path_sampler_of.h"

namespace vkpath::reference {

std::unique_ptr<PathSampler> makeSmoothAovsPathSampler(const char* name,
                                                       const wavefront::SceneTables& tables,
                                                       const shared::SceneInfo& info) {
    return std::make_unique<PathSamplerOf<VKP_CPU_FEATURES>>(name, tables, info);
}

}  // namespace vkpath::reference
