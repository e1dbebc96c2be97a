// How far a float evaluation of a rough dielectric's Fresnel term can move by
// rounding, for tests that compare two evaluations of one configuration.
#pragma once

#include <algorithm>
#include <cmath>

#include "shared/microfacet.h"

namespace vkpath::test {

// Fresnel's slope is infinite at the critical angle (1 - F grows like
// sqrt(cos - cos_c)), so there two float evaluations of one configuration
// agree only as well as F does when wo.m moves by its rounding: the half
// vector recomputed from wo and wi differs from the sampled one by a few
// ulps, bounded here by 1e-6. Returns that relative change of F (reflection)
// or of 1 - F (transmission) for the dielectric of index `ior`, wo and wi in
// its local frame; elsewhere it is ~1e-6.
inline double fresnelRounding(float ior, glm::vec3 wo, glm::vec3 wi) {
    const float side = wo.z > 0 ? 1.0f : -1.0f;
    const float eta = wo.z > 0 ? ior : 1 / ior;
    glm::vec3 m;
    if (!shared::roughDielectricHalfVector(side * wo, side * wi, eta, m)) return 0;
    const float om = glm::dot(side * wo, m);
    const double f = shared::fresnelDielectric(om, eta);
    const double change = std::max(std::abs(shared::fresnelDielectric(om + 1e-6f, eta) - f),
                                   std::abs(shared::fresnelDielectric(om - 1e-6f, eta) - f));
    const double part = wo.z * wi.z > 0 ? f : 1 - f;
    return part > 0 ? change / part : 0;
}

}  // namespace vkpath::test
