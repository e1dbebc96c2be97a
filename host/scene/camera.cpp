#include "scene/camera.h"

#include <fmt/format.h>

#include <cmath>

#include "input_error.h"

namespace vkpath::scene {

shared::Camera makeGpuCamera(const Camera& camera, uint32_t width, uint32_t height) {
    if (width == 0 || height == 0)
        throw InputError(fmt::format("film size {}x{} is empty", width, height));
    if (!(camera.xfovDegrees > 0.0f && camera.xfovDegrees < 180.0f))
        throw InputError(fmt::format("camera '{}': field of view {} degrees is not in (0, 180)",
                                     camera.name, camera.xfovDegrees));
    const glm::vec3 view = camera.target - camera.position;
    if (!(glm::length(view) > 0.0f) || !std::isfinite(glm::length(view)))
        throw InputError(fmt::format("camera '{}': target equals position", camera.name));
    const glm::vec3 forward = glm::normalize(view);
    const glm::vec3 side = glm::cross(forward, camera.up);
    if (!(glm::length(side) > 1e-6f))
        throw InputError(
            fmt::format("camera '{}': up vector is parallel to the view direction", camera.name));
    const glm::vec3 right = glm::normalize(side);
    const glm::vec3 up = glm::cross(right, forward);

    const float filmAspect = float(width) / float(height);
    const float cameraAspect = camera.aspect > 0.0f ? camera.aspect : filmAspect;
    float tanX = std::tan(glm::radians(camera.xfovDegrees) * 0.5f);
    float tanY = tanX / cameraAspect;
    if (filmAspect > tanX / tanY)
        tanX = tanY * filmAspect;  // film is wider: widen horizontally
    else
        tanY = tanX / filmAspect;  // film is taller: widen vertically

    shared::Camera gpu;
    gpu.origin = camera.position;
    gpu.forward = forward;
    gpu.right = right * tanX;
    gpu.up = up * tanY;
    gpu.width = width;
    gpu.height = height;
    return gpu;
}

}  // namespace vkpath::scene
