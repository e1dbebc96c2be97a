// The CPU reference's integrator compiled for VKP_CPU_PROFILE_CORE
// (reference/cpu_profiles.h). The define comes before every include.
#define VKP_CPU_FEATURES VKP_CPU_PROFILE_CORE
#include "reference/cpu_profiles.h"
#include "reference/path_sampler_of.h"

namespace vkpath::reference {

std::unique_ptr<PathSampler> makeCorePathSampler(const char* name,
                                                 const wavefront::SceneTables& tables,
                                                 const shared::SceneInfo& info) {
    return std::make_unique<PathSamplerOf<VKP_CPU_FEATURES>>(name, tables, info);
}

}  // namespace vkpath::reference
