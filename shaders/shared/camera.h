// The pinhole camera. The host turns position, look-at point, up vector and
// horizontal field of view into an orthogonal frame whose side vectors are
// pre-scaled by tan(fov / 2), so generating a ray costs a few multiply-adds
// and one normalisation, the same on CPU and GPU.
#ifndef VKPATH_SHARED_CAMERA_H
#define VKPATH_SHARED_CAMERA_H

#include "shared/compat.h"
#include "shared/ray.h"

VKP_NAMESPACE_BEGIN

struct Camera {
    vec3 origin;   // world space position of the pinhole
    vec3 forward;  // world space, unit: the view direction
    vec3 right;    // world space: unit right vector times tan(horizontal fov / 2)
    vec3 up;       // world space: unit up vector times tan(vertical fov / 2)
    uint width;    // film size in pixels
    uint height;
};

// The ray through film position (x + jitter.x, y + jitter.y), in pixels from
// the top-left corner of the image; jitter in [0, 1)^2 places it in the pixel.
VKP_FN Ray generateCameraRay(VKP_IN(Camera) camera, uvec2 pixel, vec2 jitter) {
    vec2 film = (vec2(pixel) + jitter) / vec2(float(camera.width), float(camera.height));
    vec2 ndc = vec2(2.0f * film.x - 1.0f, 1.0f - 2.0f * film.y);  // +y up on the image
    Ray ray;
    ray.origin = camera.origin;
    ray.direction = normalize(camera.forward + ndc.x * camera.right + ndc.y * camera.up);
    ray.tMax = 3.402823466e+38f;  // FLT_MAX: unbounded
    ray.pixel = pixel.y * camera.width + pixel.x;
    return ray;
}

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::Camera) == 56);
#endif

#endif  // VKPATH_SHARED_CAMERA_H
