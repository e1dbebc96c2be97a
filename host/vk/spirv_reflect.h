// Just enough SPIR-V reflection for vkpath: the descriptor bindings and the
// push-constant size a kernel declares (so the harness builds its layouts
// without a hand-written table), and the member offsets and array strides of
// named structs (so tests can check the GLSL layout against C++ sizeof), and
// the capabilities and execution modes it declares (so tests can check that a
// float-controls mode survived compilation).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vkpath::vk {

enum class DescriptorKind {
    StorageBuffer,
    UniformBuffer,
    UniformTexelBuffer,  // a GLSL textureBuffer / utextureBuffer
};

struct SpirvBinding {
    uint32_t set = 0;
    uint32_t binding = 0;
    DescriptorKind kind = DescriptorKind::StorageBuffer;
};

struct SpirvStructLayout {
    std::vector<uint32_t> memberOffsets;  // bytes, in declaration order
    std::optional<uint32_t> arrayStride;  // stride of a runtime array of this struct, if any
};

struct SpirvExecutionMode {
    uint32_t mode = 0;  // SPIR-V ExecutionMode enumerant, e.g. 4461 SignedZeroInfNanPreserve
    std::vector<uint32_t> operands;  // its literals, e.g. the float width
};

struct SpirvReflection {
    std::vector<SpirvBinding> bindings;  // sorted by (set, binding)
    uint32_t pushConstantSize = 0;       // bytes; 0 if there is no push-constant block
    std::map<std::string, SpirvStructLayout> structs;  // by the struct's GLSL name
    std::vector<uint32_t> capabilities;                // OpCapability operands, in module order
    std::vector<SpirvExecutionMode> executionModes;    // OpExecutionMode of the entry point(s)
};

// Throws std::runtime_error on a malformed module.
SpirvReflection reflectSpirv(std::span<const uint32_t> words);

}  // namespace vkpath::vk
