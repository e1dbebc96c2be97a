// SPIR-V compiled at build time and embedded in the binary (see
// cmake/shaders.cmake), looked up by kernel name: the shader's file name
// without extension, e.g. "generate" for shaders/stages/generate.comp.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace vkpath::shaders {

struct EmbeddedShader {
    const char* name;
    std::span<const uint32_t> spirv;
};

// The wavefront stage kernels of shaders/stages/.
std::span<const EmbeddedShader> stageKernels();

// Makes another group of embedded kernels findable (tests register theirs).
void registerKernels(std::span<const EmbeddedShader> kernels);

// The SPIR-V of the named kernel; throws std::out_of_range naming it if unknown.
std::span<const uint32_t> findKernel(std::string_view name);

}  // namespace vkpath::shaders
