// From the scene's camera to the kernels' pinhole frame for a given film size.
#pragma once

#include "scene/scene.h"
#include "shared/camera.h"

namespace vkpath::scene {

// The field of view follows Scotty3D's rule: `xfovDegrees` is horizontal for
// the camera's own aspect; for a film of another aspect the narrower axis is
// widened to fit, so nothing the camera frames is cropped. Throws InputError
// for a degenerate camera (zero or >= 180 degree fov, target at the position,
// up parallel to the view direction).
shared::Camera makeGpuCamera(const Camera& camera, uint32_t width, uint32_t height);

}  // namespace vkpath::scene
