// The VKP_FEATURE_* bits (shaders/shared/features.h) a render's kernels are
// specialised to: what its scene tables hold and what its settings ask for.
// A feature absent here has no code in the pipelines, no stage, no queue and
// no memory beyond the placeholder Vulkan needs to bind.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "shared/features.h"
#include "shared/scene_data.h"
#include "vk/kernel.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::wavefront {

// From the tables: the primitive kinds, the materials of the primitives (not
// of every material in the file), emission, the light types in the light
// list and the kind of environment.
uint64_t sceneFeatures(const SceneTables& tables);

// sceneFeatures plus the render's settings in `info` (renderSceneInfo): the
// sampler, how many light samples, whether roulette can end a path, the AOVs.
uint64_t renderFeatures(const SceneTables& tables, const shared::SceneInfo& info);

// Shadow rays per path vertex that a kernel with these features can queue
// (`lightSamples`: SceneInfo::lightSamples): none unless there is something
// to sample and a surface with a non-delta lobe to sample it from.
uint32_t shadowRaysPerVertex(uint64_t features, uint32_t lightSamples);

// The names of the set bits in declaration order, e.g. "triangles diffuse
// emissive-surfaces independent-sampler light-samples roulette"; "general"
// for VKP_FEATURES_ALL.
std::string describeFeatures(uint64_t features);

// The two 32-bit specialisation constants that hold `features`
// (shared/bindings.h VKP_SPEC_FEATURES, VKP_SPEC_FEATURES_HIGH), and the
// features that a list of constants specialises to (a word it leaves out is
// all ones, the kernels' default).
std::array<vk::SpecializationConstant, 2> featureConstants(uint64_t features);
uint64_t specializedFeatures(std::span<const vk::SpecializationConstant> constants);

// The first feature profile (shared/feature_profiles.h) that holds every bit
// of `features`: its key ("smooth", "core"...), or nullptr where none does.
const char* featureProfile(uint64_t features);

// The build of kernel `name` to run for `features`: "<name>_<key>" of their
// feature profile, whose SPIR-V lacks the code of every feature outside it
// (cmake/shaders.cmake, PROFILED), else `name`, the general build.
std::string profiledKernel(std::string_view name, uint64_t features);

}  // namespace vkpath::wavefront
