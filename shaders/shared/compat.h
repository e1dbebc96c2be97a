// Lets one header compile as GLSL (for kernels) and as C++ (for the host, the
// CPU reference and the tests). Shared code is written in the common subset:
// GLSL types and built-ins, which GLM provides on the C++ side, plus a few
// macros for what the two languages spell differently.
#ifndef VKPATH_SHARED_COMPAT_H
#define VKPATH_SHARED_COMPAT_H

#ifdef __cplusplus

#include <cstdint>
#include <glm/glm.hpp>

#define VKP_NAMESPACE_BEGIN \
    namespace vkpath::shared {  \
    using namespace glm;
#define VKP_NAMESPACE_END }
// Functions defined in shared headers: `inline` in C++ (one definition in many
// translation units), nothing in GLSL. A translation unit that compiles the
// shared code for a feature set of its own (VKP_CPU_FEATURES, shared/features.h)
// gets its own copies: `static`, so that the linker never takes one
// translation unit's copy, compiled for other features, for another's.
#ifdef VKP_CPU_FEATURES
#define VKP_FN static inline
#else
#define VKP_FN inline
#endif
// Parameters written by a function: references in C++, `inout`/`out` in GLSL.
#define VKP_INOUT(T) T&
#define VKP_OUT(T) T&
// Parameters only read: const references in C++, so that a call does not copy
// the struct to the stack (Material is 80 bytes; the copies cost the CPU
// reference about 8% on CBspheres); plain values in GLSL, where a kernel
// compiler sees through `in` copies.
#define VKP_IN(T) const T&

namespace vkpath::shared {
using uint = std::uint32_t;
using glm::floatBitsToUint;
using glm::uintBitsToFloat;
}  // namespace vkpath::shared

#else  // GLSL

#define VKP_NAMESPACE_BEGIN
#define VKP_NAMESPACE_END
#define VKP_FN
#define VKP_INOUT(T) inout T
#define VKP_OUT(T) out T
#define VKP_IN(T) T

#endif

#endif  // VKPATH_SHARED_COMPAT_H
