// What vkpath makes of a Scotty3D scene where Scotty3D is not physical or
// its files say a thing twice: the lamp-reconciliation policy and the camera
// framing. Plain functions over plain structs, so each decision is tested
// without XML (tests/scene/scotty3d_policy_test.cpp); the COLLADA reader
// (collada_loader.cpp) gathers the inputs. Each decision prints a warning
// line when it applies. SOURCE.md is ../shared/scenes/scotty3d/SOURCE.md.
//
// - A lamp described twice. Blender scenes carry an area light for Scotty3D's
//   direct lighting and a coincident emissive mesh that the camera sees; a
//   physical renderer that kept both would count the lamp twice. An area
//   light whose centre lies within 10% of its rectangle's diagonal of the
//   centroid of an emissive mesh (or the centre of an emissive sphere) is
//   dropped and the mesh is the lamp. If the mesh faces away from the way the
//   area light emits, its winding is flipped to face that way.
// - When the two disagree in radiance (area light 3, mesh 10), the area
//   light's radiance wins: in Scotty3D the area light is what lights the
//   scene (emissive surfaces are only seen, not sampled), so its value sets
//   the brightness of every reference image, while the directly seen lamp is
//   far above display white either way. The mesh gets a copy of its material
//   with that radiance.
// - An area light with no coincident emitter becomes an emissive quad: the
//   unit square of Scotty3D's AreaLight (edges M(-1,0,0) and M(0,1,0),
//   centred on M(0,0,0)) with reflectance 0, one-sided, facing M(0,0,-1), the
//   side Scotty3D's AreaLight::sample_L lights.
// - A point light within 10% of an emitter's size of its centre (CBempty: a
//   point light 1 cm from the lamp mesh) is Blender's stand-in for that same
//   lamp and is dropped: the mesh already emits, and unlike the point light
//   it is seen by the camera and in reflections. Keeping both would double
//   the lamp's power.
// - Other point lights: Scotty3D's have no falloff (irradiance = colour x
//   cos, at any distance); vkpath's fall off with the inverse square. The
//   intensity becomes colour x d^2 W/sr, d the distance to the centre of the
//   scene's bounding box, so the irradiance at the scene's centre matches
//   (colour as W/sr when d is 0). Spot lights (which Scotty3D does not
//   render) are converted the same way, with the cone from falloff_angle.
// - Scotty3D's ambient light is a hemisphere (+Y) used for direct lighting
//   only, invisible to the camera; vkpath has no such light and uses a
//   constant environment of the same radiance over the whole sphere.
// - Camera framing follows SOURCE.md's rule (see frameScotty3dCamera).
#pragma once

#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene {

// Scotty3D's area light: a rectangle emitting from one side.
struct Scotty3dAreaLight {
    std::string name;
    glm::vec3 center, edgeX, edgeY;  // world space; edges are full side vectors
    glm::vec3 direction;             // unit, the way it emits
    glm::vec3 radiance;
};

// Scotty3D's point light (or a spot light, which Scotty3D does not render).
struct Scotty3dPointLight {
    std::string name;
    glm::vec3 position;
    glm::vec3 color;                // Scotty3D's value: irradiance, no falloff
    std::optional<SpotLight> spot;  // set for spot lights (direction and cone)
};

// The lights of a Scotty3D file that the policy decides on. Directional
// lights need no decision: the reader adds them to the scene itself.
struct Scotty3dLights {
    std::vector<Scotty3dAreaLight> areaLights;
    std::vector<Scotty3dPointLight> pointLights;
    std::optional<glm::vec3> ambient;  // the sum of the ambient lights' radiance
};

// Adds `lights` to `scene`, whose meshes, spheres and materials are the
// file's geometry, as the decisions above say: merges lamps described twice
// (changing the lamp mesh's winding or material where needed), makes quads
// of area lights without a lamp, converts point and spot lights to inverse
// square about `sceneCenter`, and the ambient light to a constant
// environment.
void reconcileScotty3dLights(const Scotty3dLights& lights, const glm::vec3& sceneCenter,
                             Scene& scene, ImportWarnings& warnings);

// SOURCE.md, "How Scotty3D frames these scenes": keeps only the direction of
// the COLLADA camera (`cameraWorld`, its node's world matrix, already turned
// +Y up; none when the file has no camera: the view is from +Z) and re-aims
// it at the centre of the bounds of the meshes and spheres from 1.5 times
// their diagonal. Sets the camera's position, target and up; leaves its
// optics alone.
void frameScotty3dCamera(const std::optional<glm::dmat4>& cameraWorld, const glm::vec3& boundsMin,
                         const glm::vec3& boundsMax, Camera& camera);

}  // namespace vkpath::scene
