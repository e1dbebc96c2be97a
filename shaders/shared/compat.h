// Lets one header compile as GLSL (for kernels) and as C++ (for the host, the
// CPU reference and the tests). Shared code is written in the common subset:
// GLSL types and built-ins, which GLM provides on the C++ side, plus a few
// macros for what the two languages spell differently.
#ifndef VKPATH_SHARED_COMPAT_H
#define VKPATH_SHARED_COMPAT_H

#ifdef __cplusplus

#include <cstdint>
#include <glm/glm.hpp>
#ifdef __GFNI__
#include <immintrin.h>
#endif

#define VKP_NAMESPACE_BEGIN    \
    namespace vkpath::shared { \
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
// the struct to the stack (Material is 176 bytes; docs/BENCHMARKS.md, "What
// each part of its design buys"); plain values in GLSL, where a kernel
// compiler sees through `in` copies.
#define VKP_IN(T) const T&
// A named 32-bit unsigned constant at file scope, usable in switch cases and
// constant expressions (what the registries' tables make: VKP_MATERIAL_*,
// VKP_LIGHT_*, the material kinds' VKP_FEATURE_*).
#define VKP_CONSTANT(name, value) inline constexpr unsigned name = value;

namespace vkpath::shared {
using uint = std::uint32_t;
using glm::floatBitsToUint;
using glm::uintBitsToFloat;

// GLSL's bitfieldReverse, which the Sobol' sampler calls four times per pair
// of numbers (shared/sobol.h). x86 has no instruction for it; GLM's shifts
// and masks take 18 instructions. With GFNI (Intel since Ice Lake, AMD since
// Zen 4) one affine transform over GF(2) reverses the bits of each byte (the
// matrix 0x8040201008040201 maps bit i to bit 7 - i; Intel's intrinsics
// guide, _mm_gf2p8affine_epi64_epi8) and a byte swap finishes
// (docs/BENCHMARKS.md, "Samplers" and "What each part of its design buys").
// A function in this namespace hides GLM's template for the shared code.
inline uint bitfieldReverse(uint x) {
#ifdef __GFNI__
    const __m128i perByte = _mm_gf2p8affine_epi64_epi8(_mm_cvtsi32_si128(int(x)),
                                                       _mm_set1_epi64x(0x8040201008040201LL), 0);
    return __builtin_bswap32(uint(_mm_cvtsi128_si32(perByte)));
#else
    return glm::bitfieldReverse(x);
#endif
}
}  // namespace vkpath::shared

#else  // GLSL

#define VKP_NAMESPACE_BEGIN
#define VKP_NAMESPACE_END
#define VKP_FN
#define VKP_INOUT(T) inout T
#define VKP_OUT(T) out T
#define VKP_IN(T) T
#define VKP_CONSTANT(name, value) const uint name = value;

#endif

#endif  // VKPATH_SHARED_COMPAT_H
