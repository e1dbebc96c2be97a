// The Scotty3D policy (scene/scotty3d_policy.h) without XML: each test
// builds the policy's input (the file's geometry as a scene, the lights the
// COLLADA reader gathered) and checks the decision against numbers worked
// out by hand.
#include "scene/scotty3d_policy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "scene/import_warnings.h"

namespace {

using namespace vkpath::scene;

// A 1 x 1 m emissive square in the plane y = `height`, centred on the
// origin, whose front (counter-clockwise) faces `facingDown` ? -Y : +Y.
Scene sceneWithLampMesh(float height, bool facingDown, glm::vec3 radiance) {
    Scene scene;
    Material lamp;
    lamp.name = "lamp";
    lamp.reflectance = glm::vec3(0.0f);
    lamp.emission = radiance;
    scene.materials.push_back(lamp);
    Mesh mesh;
    mesh.name = "Lamp";
    mesh.positions = {
        {-0.5f, height, -0.5f}, {0.5f, height, -0.5f}, {0.5f, height, 0.5f}, {-0.5f, height, 0.5f}};
    // (p1 - p0) x (p2 - p0) = (1, 0, 0) x (1, 0, 1) = (0, -1, 0): faces -Y.
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    if (!facingDown)
        for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
    mesh.normals = std::vector<glm::vec3>(4, glm::vec3(0, facingDown ? -1 : 1, 0));
    scene.meshes.push_back(mesh);
    return scene;
}

// An area light of `size` x `size` m at `center` emitting straight down.
Scotty3dAreaLight areaLightDown(glm::vec3 center, float size, glm::vec3 radiance) {
    return {"Area", center, {-size, 0, 0}, {0, 0, size}, {0, -1, 0}, radiance};
}

glm::vec3 frontNormal(const Mesh& mesh, size_t t) {
    const glm::uvec3 tri = mesh.triangles[t];
    return glm::normalize(glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                     mesh.positions[tri.z] - mesh.positions[tri.x]));
}

std::vector<std::string> reconcile(const Scotty3dLights& lights, glm::vec3 sceneCenter,
                                   Scene& scene) {
    ImportWarnings warnings("policy.dae");
    reconcileScotty3dLights(lights, sceneCenter, scene, warnings);
    return warnings.lines();
}

bool anyContains(const std::vector<std::string>& lines, const std::string& text) {
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

TEST(ColladaScotty3dPolicy, AreaLightAtTheLampMeshIsDroppedAndTheMeshEmits) {
    Scene scene = sceneWithLampMesh(2.0f, true, glm::vec3(5.0f));
    Scotty3dLights lights;
    // 0.05 m from the mesh's centroid; 10% of the 1 m light's diagonal is 0.141 m.
    lights.areaLights.push_back(areaLightDown({0.05f, 2.0f, 0.0f}, 1.0f, glm::vec3(5.0f)));
    const auto warnings = reconcile(lights, glm::vec3(0.0f), scene);
    ASSERT_EQ(scene.meshes.size(), 1u);  // no quad added
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.meshes[0].material, 0u);
    EXPECT_EQ(scene.materials[0].emission, glm::vec3(5.0f));
    EXPECT_NEAR(frontNormal(scene.meshes[0], 0).y, -1.0f, 1e-6f);  // unchanged
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(anyContains(warnings, "describe one lamp")) << warnings[0];
    EXPECT_TRUE(scene.pointLights.empty());
    EXPECT_FALSE(scene.environment.has_value());
}

TEST(ColladaScotty3dPolicy, DisagreeingRadianceTakesTheAreaLightsOnACopyOfTheMaterial) {
    Scene scene = sceneWithLampMesh(2.0f, true, glm::vec3(10.0f));
    Scotty3dLights lights;
    lights.areaLights.push_back(areaLightDown({0.0f, 2.0f, 0.0f}, 1.0f, glm::vec3(3.0f)));
    const auto warnings = reconcile(lights, glm::vec3(0.0f), scene);
    ASSERT_EQ(scene.materials.size(), 2u);
    EXPECT_EQ(scene.materials[0].emission, glm::vec3(10.0f));  // the file's material is kept
    EXPECT_EQ(scene.meshes[0].material, 1u);
    EXPECT_EQ(scene.materials[1].emission, glm::vec3(3.0f));
    EXPECT_EQ(scene.materials[1].reflectance, glm::vec3(0.0f));
    EXPECT_TRUE(anyContains(warnings, "disagree"));
}

TEST(ColladaScotty3dPolicy, LampMeshFacingAwayIsTurnedToTheAreaLightsDirection) {
    Scene scene = sceneWithLampMesh(2.0f, false, glm::vec3(5.0f));
    ASSERT_NEAR(frontNormal(scene.meshes[0], 0).y, 1.0f, 1e-6f);
    Scotty3dLights lights;
    lights.areaLights.push_back(areaLightDown({0.0f, 2.0f, 0.0f}, 1.0f, glm::vec3(5.0f)));
    const auto warnings = reconcile(lights, glm::vec3(0.0f), scene);
    for (size_t t = 0; t < scene.meshes[0].triangles.size(); ++t)
        EXPECT_NEAR(frontNormal(scene.meshes[0], t).y, -1.0f, 1e-6f);
    for (const glm::vec3& n : scene.meshes[0].normals) EXPECT_EQ(n, glm::vec3(0, -1, 0));
    EXPECT_TRUE(anyContains(warnings, "turned to face"));
}

TEST(ColladaScotty3dPolicy, AreaLightAwayFromEveryEmitterBecomesAQuad) {
    // 0.2 m from the lamp mesh: beyond 10% of the 1 m light's 1.414 m diagonal.
    Scene scene = sceneWithLampMesh(2.0f, true, glm::vec3(5.0f));
    Scotty3dLights lights;
    lights.areaLights.push_back(
        areaLightDown({0.2f, 2.0f, 0.0f}, 1.0f, glm::vec3(4.0f, 3.0f, 2.0f)));
    const auto warnings = reconcile(lights, glm::vec3(0.0f), scene);
    ASSERT_EQ(scene.meshes.size(), 2u);
    const Mesh& quad = scene.meshes[1];
    ASSERT_EQ(quad.positions.size(), 4u);
    ASSERT_EQ(quad.triangles.size(), 2u);
    const Material& material = scene.materials[quad.material];
    EXPECT_EQ(material.emission, glm::vec3(4.0f, 3.0f, 2.0f));
    EXPECT_EQ(material.reflectance, glm::vec3(0.0f));
    float area = 0.0f;
    for (size_t t = 0; t < 2; ++t) {
        EXPECT_NEAR(frontNormal(quad, t).y, -1.0f, 1e-6f);  // faces the way the light emits
        const glm::uvec3 tri = quad.triangles[t];
        area += 0.5f * glm::length(glm::cross(quad.positions[tri.y] - quad.positions[tri.x],
                                              quad.positions[tri.z] - quad.positions[tri.x]));
    }
    EXPECT_NEAR(area, 1.0f, 1e-6f);
    for (const glm::vec3& p : quad.positions) {
        EXPECT_FLOAT_EQ(p.y, 2.0f);
        EXPECT_NEAR(std::abs(p.x - 0.2f), 0.5f, 1e-6f);
        EXPECT_NEAR(std::abs(p.z), 0.5f, 1e-6f);
    }
    EXPECT_TRUE(anyContains(warnings, "has no emissive mesh at its centre"));
}

TEST(ColladaScotty3dPolicy, AreaLightAtAnEmissiveSphereIsDropped) {
    Scene scene;
    Material glow;
    glow.emission = glm::vec3(2.0f);
    scene.materials.push_back(glow);
    scene.spheres.push_back({"Bulb", {0.0f, 1.0f, 0.0f}, 0.1f, 0});
    Scotty3dLights lights;
    lights.areaLights.push_back(areaLightDown({0.0f, 1.0f, 0.0f}, 0.2f, glm::vec3(2.0f)));
    const auto warnings = reconcile(lights, glm::vec3(0.0f), scene);
    EXPECT_TRUE(scene.meshes.empty());
    EXPECT_TRUE(anyContains(warnings, "emissive sphere 'Bulb'"));
}

TEST(ColladaScotty3dPolicy, PointLightAtTheLampIsDroppedOthersFallOffFromTheSceneCentre) {
    Scene scene = sceneWithLampMesh(2.0f, true, glm::vec3(5.0f));
    Scotty3dLights lights;
    // The lamp's bounding-box diagonal is sqrt(2) m: 0.1 m away is the same lamp.
    lights.pointLights.push_back({"Stand-in", {0.0f, 1.9f, 0.0f}, glm::vec3(1.0f), std::nullopt});
    // 3 m from the scene centre at (0, 0, 4): intensity = colour x 9.
    lights.pointLights.push_back(
        {"Key", {0.0f, 0.0f, 7.0f}, glm::vec3(2.0f, 1.0f, 0.5f), std::nullopt});
    // At the scene centre: colour as W/sr.
    lights.pointLights.push_back({"Centre", {0.0f, 0.0f, 4.0f}, glm::vec3(0.25f), std::nullopt});
    const auto warnings = reconcile(lights, {0.0f, 0.0f, 4.0f}, scene);
    ASSERT_EQ(scene.pointLights.size(), 2u);
    EXPECT_EQ(scene.pointLights[0].position, glm::vec3(0.0f, 0.0f, 7.0f));
    EXPECT_NEAR(scene.pointLights[0].intensity.x, 18.0f, 1e-4f);
    EXPECT_NEAR(scene.pointLights[0].intensity.y, 9.0f, 1e-4f);
    EXPECT_NEAR(scene.pointLights[0].intensity.z, 4.5f, 1e-4f);
    EXPECT_EQ(scene.pointLights[1].intensity, glm::vec3(0.25f));
    EXPECT_TRUE(anyContains(warnings, "point light 'Stand-in'"));
    EXPECT_TRUE(anyContains(warnings, "no falloff"));
}

TEST(ColladaScotty3dPolicy, SpotLightsKeepTheirConeAndAreNeverMerged) {
    Scene scene = sceneWithLampMesh(2.0f, true, glm::vec3(5.0f));
    SpotLight cone;
    cone.direction = {0, -1, 0};
    cone.innerConeAngle = 0.2f;
    cone.outerConeAngle = 0.4f;
    Scotty3dLights lights;
    lights.pointLights.push_back({"Spot", {0.0f, 1.95f, 0.0f}, glm::vec3(1.0f), cone});
    reconcile(lights, {0.0f, 0.0f, 0.0f}, scene);
    ASSERT_EQ(scene.spotLights.size(), 1u);
    EXPECT_TRUE(scene.pointLights.empty());
    const SpotLight& spot = scene.spotLights[0];
    EXPECT_EQ(spot.position, glm::vec3(0.0f, 1.95f, 0.0f));
    EXPECT_EQ(spot.direction, glm::vec3(0, -1, 0));
    EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.2f);
    EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.4f);
    EXPECT_NEAR(spot.intensity.x, 1.95f * 1.95f, 1e-5f);
}

TEST(ColladaScotty3dPolicy, AmbientBecomesAConstantEnvironment) {
    Scene scene = sceneWithLampMesh(2.0f, true, glm::vec3(5.0f));
    Scotty3dLights lights;
    lights.ambient = glm::vec3(0.1f, 0.2f, 0.3f);
    reconcile(lights, glm::vec3(0.0f), scene);
    ASSERT_TRUE(scene.environment.has_value());
    EXPECT_FALSE(scene.environment->map.has_value());
    EXPECT_EQ(scene.environment->color, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_FLOAT_EQ(scene.environment->strength, 1.0f);
}

TEST(ColladaScotty3dPolicy, NoLightsChangeNothing) {
    Scene scene = sceneWithLampMesh(2.0f, true, glm::vec3(5.0f));
    const auto warnings = reconcile({}, glm::vec3(0.0f), scene);
    EXPECT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.materials.size(), 1u);
    EXPECT_TRUE(warnings.empty());
    EXPECT_FALSE(scene.environment.has_value());
}

// ---- camera framing (SOURCE.md steps 2-5) --------------------------------

TEST(ColladaScotty3dPolicy, WithoutACameraTheSceneIsSeenFromPlusZ) {
    Camera camera;
    frameScotty3dCamera(std::nullopt, {-1, -1, -1}, {1, 1, 1}, camera);
    const float r = 1.5f * std::sqrt(12.0f);
    EXPECT_EQ(camera.target, glm::vec3(0.0f));
    EXPECT_NEAR(camera.position.x, 0.0f, 1e-5f);
    EXPECT_NEAR(camera.position.y, 0.0f, 1e-5f);
    EXPECT_NEAR(camera.position.z, r, 1e-5f);
    EXPECT_EQ(camera.up, glm::vec3(0, 1, 0));
}

TEST(ColladaScotty3dPolicy, TheCamerasDirectionIsItsViewVectorTransformedAsAPoint) {
    // A camera at (0, 0, 5) looking down -Z: M(0,0,-1,1) = (0, 0, 4), so the
    // camera sits on +Z of the bounds' centre, 1.5 diagonals away, whatever
    // its own position.
    glm::dmat4 world(1.0);
    world[3] = glm::dvec4(0, 0, 5, 1);
    Camera camera;
    frameScotty3dCamera(world, {0, 0, 0}, {2, 2, 2}, camera);
    const float r = 1.5f * std::sqrt(12.0f);
    EXPECT_EQ(camera.target, glm::vec3(1.0f));
    EXPECT_NEAR(camera.position.x, 1.0f, 1e-5f);
    EXPECT_NEAR(camera.position.y, 1.0f, 1e-5f);
    EXPECT_NEAR(camera.position.z, 1.0f + r, 1e-5f);

    // Moved to (3, 0, 0): the point is (3, 0, -1), so the camera moves off
    // axis towards +X and -Z, though it still looks down -Z.
    world[3] = glm::dvec4(3, 0, 0, 1);
    frameScotty3dCamera(world, {0, 0, 0}, {2, 2, 2}, camera);
    const glm::vec3 offset = glm::normalize(camera.position - camera.target);
    EXPECT_NEAR(offset.x, 3.0f / std::sqrt(10.0f), 1e-5f);
    EXPECT_NEAR(offset.z, -1.0f / std::sqrt(10.0f), 1e-5f);
    EXPECT_NEAR(glm::length(camera.position - camera.target), r, 1e-4f);
}

TEST(ColladaScotty3dPolicy, ACameraStraightAboveTakesMinusZAsUp) {
    // Rotated to look down -Y from above the origin: M(0,0,-1,1) = (0, 4, 0).
    glm::dmat4 world(1.0);
    world[1] = glm::dvec4(0, 0, -1, 0);
    world[2] = glm::dvec4(0, 1, 0, 0);
    world[3] = glm::dvec4(0, 5, 0, 1);
    Camera camera;
    frameScotty3dCamera(world, {-1, -1, -1}, {1, 1, 1}, camera);
    EXPECT_NEAR(camera.position.y, 1.5f * std::sqrt(12.0f), 1e-5f);
    EXPECT_EQ(camera.up, glm::vec3(0, 0, -1));
}

TEST(ColladaScotty3dPolicy, FramingLeavesTheOpticsAlone) {
    Camera camera;
    camera.name = "Camera";
    camera.xfovDegrees = 35.0f;
    camera.aspect = 1.5f;
    frameScotty3dCamera(std::nullopt, {0, 0, 0}, {1, 1, 1}, camera);
    EXPECT_EQ(camera.name, "Camera");
    EXPECT_EQ(camera.xfovDegrees, 35.0f);
    EXPECT_EQ(camera.aspect, 1.5f);
}

}  // namespace
