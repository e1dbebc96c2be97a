// Inverse trigonometry with a known error on every device. Vulkan lets
// atan, asin and acos be off by 4096 ulp (SPIR-V environment, precision
// table), and lavapipe's are off by ~2e-4 relative: enough to move an
// environment-map lookup into the neighbouring texel. These polynomials give
// ~1e-7 absolute on CPU and GPU alike.
#ifndef VKPATH_SHARED_PRECISE_MATH_H
#define VKPATH_SHARED_PRECISE_MATH_H

#include "shared/compat.h"
#include "shared/constants.h"

VKP_NAMESPACE_BEGIN

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
