// Rays as they travel between stages.
#ifndef VKPATH_SHARED_RAY_H
#define VKPATH_SHARED_RAY_H

#include "shared/compat.h"

VKP_NAMESPACE_BEGIN

struct Ray {
    vec3 origin;     // world space
    float tMax;      // the ray is the segment origin + t * direction, 0 <= t < tMax
    vec3 direction;  // world space, unit length
    uint pixel;      // index of the film pixel the ray's path belongs to (y * width + x)
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::Ray) == 32);
#endif

#endif  // VKPATH_SHARED_RAY_H
