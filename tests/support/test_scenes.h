// Small analytic scenes shared by the render tests.
#pragma once

#include "scene/scene.h"
#include "shared/material.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::test {

// A unit sphere of material `kind` at the origin under a constant white
// environment, seen from (0, 0, 4) with a 40 degree field of view: the
// furnace scenes (a white diffuse sphere is invisible, a grey one reflects its
// albedo, a mirror shows its reflectance).
inline scene::Scene sphereInEnvironment(scene::MaterialKind kind, glm::vec3 reflectance,
                                        float ior = 1.5f) {
    scene::Scene s;
    scene::Material m;
    m.kind = kind;
    m.reflectance = reflectance;
    m.ior = ior;
    s.materials.push_back(m);
    s.spheres.push_back({"ball", glm::vec3(0.0f), 1.0f, 0});
    s.camera.position = {0.0f, 0.0f, 4.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.xfovDegrees = 40.0f;
    scene::Environment env;
    env.color = glm::vec3(1.0f);
    s.environment = env;
    return s;
}

// The camera at the centre of a black sphere of radius `radius` whose
// inside emits 1, looking along -z with a 90 degree field of view: every
// camera ray travels `radius` to the light (the media's Beer-Lambert tests).
inline scene::Scene cameraInsideALampSphere(float radius) {
    scene::Scene s;
    scene::Material lamp;
    lamp.reflectance = glm::vec3(0.0f);
    lamp.emission = glm::vec3(1.0f);
    s.materials.push_back(lamp);
    s.spheres.push_back({"lamp", glm::vec3(0.0f), radius, 0});
    s.camera.position = glm::vec3(0.0f);
    s.camera.target = {0.0f, 0.0f, -1.0f};
    s.camera.xfovDegrees = 90.0f;
    return s;
}

// The tables of a unit sphere of material `m`, as the renderer makes them.
inline wavefront::SceneTables sphereTables(const scene::Material& m) {
    scene::Scene s;
    s.materials.push_back(m);
    s.spheres.push_back({"ball", glm::vec3(0.0f), 1.0f, 0});
    return wavefront::buildSceneTables(s);
}

// The kernels' record of `m`: the host's own conversion, so that tests of
// the shared BSDF code test scene::Material's fields.
inline shared::Material gpuMaterial(const scene::Material& m) {
    return sphereTables(m).materials.at(0);
}

}  // namespace vkpath::test
