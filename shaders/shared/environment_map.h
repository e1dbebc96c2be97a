// The equirectangular (latitude-longitude) mapping between directions and
// environment-map coordinates, shared by the kernels, the CPU reference, the
// host's importance-sampling tables and the asset generator (tools/make-assets
// repeats the formula in Python).
//
// Orientation (world space, right-handed, +Y up):
//   - v = 0 is the top row of the image and looks straight up (+Y); v = 0.5 is
//     the horizon; v = 1, the bottom row, looks straight down (-Y).
//   - u = 0 (the left edge) looks along -Z; u increases towards +X (u = 0.25),
//     then +Z (u = 0.5, the centre of the image), then -X (u = 0.75).
// Seen from inside the sphere, the image is not mirrored: standing at the
// origin facing the image centre (+Z) with +Y up, +X is on the left, and so is
// u = 0.25. With theta = pi v (polar angle from +Y) and phi = 2 pi u:
//   direction = (sin theta sin phi, cos theta, -sin theta cos phi).
// The solid angle of a texel is (2 pi / width) (pi / height) sin theta.
#ifndef VKPATH_SHARED_ENVIRONMENT_MAP_H
#define VKPATH_SHARED_ENVIRONMENT_MAP_H

#include "shared/compat.h"
#include "shared/precise_math.h"

VKP_NAMESPACE_BEGIN

// Unit direction for map coordinates (u, v) in [0, 1]^2.
VKP_FN vec3 equirectDirection(float u, float v) {
    float phi = 6.28318530717958647692f * u;  // 2 pi u
    float theta = 3.14159265358979323846f * v;
    float sinTheta = sin(theta);
    return vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi));
}

// Map coordinates of a unit direction: u in [0, 1), v in [0, 1] (through
// precise_math.h: the built-in atan/acos may be off by 4096 ulp). The inverse
// of equirectDirection except at the poles, where every u is the same point
// (u = 0 is returned for the direction (0, +-1, 0)).
VKP_FN vec2 equirectUv(vec3 direction) {
    float u = 0.0f;
    if (direction.x != 0.0f || direction.z != 0.0f) {
        u = preciseAtan2(direction.x, -direction.z) *
            0.15915494309189533577f;  // / (2 pi): [-1/2, 1/2]
        if (u < 0.0f) u += 1.0f;
        if (u >= 1.0f) u = 0.0f;  // -tiny + 1 rounds to 1
    }
    float v = preciseAcos(direction.y) * 0.31830988618379067154f;  // / pi
    return vec2(u, v);
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_ENVIRONMENT_MAP_H
