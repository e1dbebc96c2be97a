// Unit vectors in one 32-bit word: the octahedral map (Meyer et al.,
// "On floating-point normal vectors", EGSR 2010; Cigolle et al., "A Survey
// of Efficient Representations for Independent Unit Vectors", JCGT 3(2),
// 2014), two signed 16-bit coordinates, within 2^-15 radians of the vector.
// A path keeps its last vertex's normal so (shared/path_state.h), for the
// light tree's importance (shared/light_tree.h): the decoded word, the same
// in the light sample taken there and in the MIS weight of the emitter that
// its BSDF sample reaches.
#ifndef VKPATH_SHARED_UNIT_VECTOR_H
#define VKPATH_SHARED_UNIT_VECTOR_H

#include "shared/compat.h"

// A word encodeUnitVector never gives (its snorm halves stop at -32767):
// "no normal", the path's last vertex a scattering event in a medium.
#define VKP_NO_NORMAL 0x80008000u

VKP_NAMESPACE_BEGIN

// +1 or -1 per component, +1 at zero.
VKP_FN vec2 signNotZero(vec2 v) {
    return vec2(v.x >= 0.0f ? 1.0f : -1.0f, v.y >= 0.0f ? 1.0f : -1.0f);
}

VKP_FN uint encodeUnitVector(vec3 n) {
    vec2 p = vec2(n.x, n.y) * (1.0f / (abs(n.x) + abs(n.y) + abs(n.z)));
    if (n.z < 0.0f) p = (vec2(1.0f) - abs(vec2(p.y, p.x))) * signNotZero(p);
    return packSnorm2x16(p);
}

VKP_FN vec3 decodeUnitVector(uint word) {
    vec2 p = unpackSnorm2x16(word);
    vec3 n = vec3(p.x, p.y, 1.0f - abs(p.x) - abs(p.y));
    if (n.z < 0.0f) {
        vec2 folded = (vec2(1.0f) - abs(vec2(n.y, n.x))) * signNotZero(vec2(n.x, n.y));
        n.x = folded.x;
        n.y = folded.y;
    }
    return normalize(n);
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_UNIT_VECTOR_H
