// Float controls for every kernel that runs the shared math: the
// SignedZeroInfNanPreserve execution mode (SPIR-V 1.4 core, Vulkan 1.2
// shaderSignedZeroInfNanPreserveFloat32, which vk::Context requires) for
// 32-bit floats. Without it a compiler may assume that no float is NaN or
// infinite and fold away the checks that keep them out of the film: the bit
// tests of stage "accumulate", and comparisons written to fail on NaN such as
// !(pdf > 0.0) and !(t >= 0.0 && t < tMax). GLSL has no syntax for the mode,
// so it is declared through GL_EXT_spirv_intrinsics: capability 4466 is
// SignedZeroInfNanPreserve, execution mode 4461 the same with the float width.
// Include before any declaration (an #extension must precede code).
#extension GL_EXT_spirv_intrinsics : require
spirv_execution_mode(capabilities = [4466], 4461, 32);
