// Math with a known error on every device.
//
// Inverse trigonometry: Vulkan lets atan, asin and acos be off by 4096 ulp
// (SPIR-V environment, precision table), and lavapipe's are off by ~2e-4
// relative: enough to move an environment-map lookup into the neighbouring
// texel. These polynomials give ~1e-7 absolute on CPU and GPU alike.
//
// dot, cross and mix written out: a GPU compiler may evaluate the built-ins
// (OpDot, GLSL.std.450 Cross and FMix) with fused multiply-adds, differently
// in each kernel that inlines them, and NoContraction (which the host puts on
// every float multiply and add: vk/spirv_no_contraction.h) does not reach
// inside an extended instruction. Written out, each product and sum is
// rounded on its own, in glm's order, on the CPU and in every GPU kernel
// alike (NVIDIA's driver gave the megakernel and the wavefront different
// bits for a normal-mapped scene with the built-ins).
#ifndef VKPATH_SHARED_PRECISE_MATH_H
#define VKPATH_SHARED_PRECISE_MATH_H

#include "shared/compat.h"
#include "shared/constants.h"

// GLSL's `precise`: no fusing or reassociation of what computes the variable
// (the C++ side is built with -ffp-contract=off instead).
#ifdef __cplusplus
#define VKP_PRECISE
#else
#define VKP_PRECISE precise
#endif

VKP_NAMESPACE_BEGIN

// dot(a, b) as glm::dot computes it: (a.x b.x + a.y b.y) + a.z b.z.
VKP_FN float exactDot(vec3 a, vec3 b) {
    VKP_PRECISE float d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}

// cross(a, b) as glm::cross computes it.
VKP_FN vec3 exactCross(vec3 a, vec3 b) {
    VKP_PRECISE vec3 c = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
    return c;
}

// mix(a, b, t) as glm::mix computes it: a (1 - t) + b t.
VKP_FN vec4 exactMix(vec4 a, vec4 b, float t) {
    VKP_PRECISE vec4 m = a * (1.0f - t) + b * t;
    return m;
}

// atan(x) for |x| <= 1: Abramowitz and Stegun, Handbook of Mathematical
// Functions, 4.4.49 (|error| <= 2e-8).
VKP_FN float atanUnit(float x) {
    float x2 = x * x;
    float p = 0.0028662257f;
    p = p * x2 - 0.0161657367f;
    p = p * x2 + 0.0429096138f;
    p = p * x2 - 0.0752896400f;
    p = p * x2 + 0.1065626393f;
    p = p * x2 - 0.1420889944f;
    p = p * x2 + 0.1999355085f;
    p = p * x2 - 0.3333314528f;
    return x + x * x2 * p;
}

// atan2(y, x) in (-pi, pi]; 0 for (0, 0).
VKP_FN float preciseAtan2(float y, float x) {
    float ax = abs(x);
    float ay = abs(y);
    if (ax == 0.0f && ay == 0.0f) return 0.0f;
    // Reduce to |ratio| <= 1, then unfold the octant.
    float a = ay <= ax ? atanUnit(ay / ax) : 0.5f * VKP_PI - atanUnit(ax / ay);
    if (x < 0.0f) a = VKP_PI - a;
    return y < 0.0f ? -a : a;
}

// acos(c) for c in [-1, 1], as atan2(sqrt(1 - c^2), c) with 1 - c^2
// factored so that c near +-1 keeps its precision.
VKP_FN float preciseAcos(float c) {
    c = clamp(c, -1.0f, 1.0f);
    return preciseAtan2(sqrt((1.0f - c) * (1.0f + c)), c);
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_PRECISE_MATH_H
