// Every floating-point multiply, add and dot product of a SPIR-V module
// decorated NoContraction, so that no GPU compiler fuses them into FMAs.
//
// Vulkan requires +, - and * to be correctly rounded, but lets a compiler fuse
// a multiply and an add (one rounding instead of two) wherever no NoContraction
// decoration forbids it. Where it fuses depends on the code around the
// operations: on NVIDIA's driver the megakernel (whose stages run inline in
// one invocation) and the wavefront stages gave images that differ in their
// last bits, and GPU traversal missed spheres the CPU hit (measured on an H200,
// docs/BENCHMARKS.md "An NVIDIA H200"). GLSL's `precise` forbids fusing only
// for the variables it qualifies; this pass forbids it everywhere, so that
// every kernel form and the CPU reference (built with -ffp-contract=off)
// round each operation alike. lavapipe does not fuse, so it changes nothing
// there.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace vkpath::vk {

// The module with an OpDecorate NoContraction for the result of every OpFAdd,
// OpFSub, OpFMul, OpFDiv, OpVectorTimesScalar, OpMatrixTimes*, OpOuterProduct
// and OpDot that lacks one, inserted after the module's other annotations.
// Throws std::runtime_error on a module that is not SPIR-V.
std::vector<uint32_t> decorateNoContraction(std::span<const uint32_t> module);

}  // namespace vkpath::vk
