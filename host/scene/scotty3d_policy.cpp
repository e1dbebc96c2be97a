#include "scene/scotty3d_policy.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vkpath::scene {
namespace {

std::string vecString(const glm::vec3& v) {
    return fmt::format("({:g}, {:g}, {:g})", v.x, v.y, v.z);
}

// A surface that emits, with where it is and how big, to recognise a lamp
// that the file also describes as a light.
struct Emitter {
    bool sphere;
    uint32_t index;  // into Scene::meshes or Scene::spheres
    glm::vec3 center;
    float size;        // bounding-box diagonal
    glm::vec3 normal;  // area-weighted mean normal (meshes), zero for spheres
};

std::vector<Emitter> emitters(const Scene& scene) {
    std::vector<Emitter> out;
    for (uint32_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& mesh = scene.meshes[i];
        if (!scene.materials[mesh.material].emissive()) continue;
        glm::dvec3 weighted(0.0), normal(0.0);
        double area = 0;
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (const glm::uvec3& t : mesh.triangles) {
            const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
            const glm::dvec3 cross = glm::cross(b - a, c - a);
            const double twiceArea = glm::length(cross);
            weighted += twiceArea * (a + b + c) / 3.0;
            normal += cross;
            area += twiceArea;
            for (int k = 0; k < 3; ++k) {
                lo = glm::min(lo, mesh.positions[t[k]]);
                hi = glm::max(hi, mesh.positions[t[k]]);
            }
        }
        if (!(area > 0)) continue;
        const double normalLength = glm::length(normal);
        out.push_back({false, i, glm::vec3(weighted / area), glm::length(hi - lo),
                       normalLength > 0 ? glm::vec3(normal / normalLength) : glm::vec3(0.0f)});
    }
    for (uint32_t i = 0; i < scene.spheres.size(); ++i) {
        const Sphere& s = scene.spheres[i];
        if (scene.materials[s.material].emissive())
            out.push_back({true, i, s.center, 2.0f * std::sqrt(3.0f) * s.radius, glm::vec3(0.0f)});
    }
    return out;
}

void addAreaLightQuad(const Scotty3dAreaLight& light, Scene& scene) {
    Material material;
    material.name = fmt::format("area light '{}'", light.name);
    material.reflectance = glm::vec3(0.0f);  // a light, not a reflector
    material.emission = light.radiance;
    Mesh mesh;
    mesh.name = material.name;
    mesh.material = static_cast<uint32_t>(scene.materials.size());
    scene.materials.push_back(material);
    const glm::vec3 hx = 0.5f * light.edgeX, hy = 0.5f * light.edgeY;
    mesh.positions = {light.center - hx - hy, light.center + hx - hy, light.center + hx + hy,
                      light.center - hx + hy};
    // Counter-clockwise seen from the side it lights, so the front faces it.
    if (glm::dot(glm::cross(light.edgeX, light.edgeY), light.direction) >= 0)
        mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    else
        mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
    scene.meshes.push_back(std::move(mesh));
}

}  // namespace

void reconcileScotty3dLights(const Scotty3dLights& lights, const glm::vec3& sceneCenter,
                             Scene& scene, ImportWarnings& warnings) {
    // ---- area lights: the lamp mesh if there is one, else a quad -----------
    for (const Scotty3dAreaLight& light : lights.areaLights) {
        const float tolerance = 0.1f * glm::length(light.edgeX + light.edgeY);
        const Emitter* match = nullptr;
        float best = tolerance;
        const std::vector<Emitter> all = emitters(scene);
        for (const Emitter& e : all) {
            const float distance = glm::length(e.center - light.center);
            if (distance <= best) {
                best = distance;
                match = &e;
            }
        }
        if (!match) {
            warnings.addExample("area-quad",
                                fmt::format("area light '{}' has no emissive mesh at its centre; "
                                            "rendered as an emissive {:g} x {:g} m quad facing {}",
                                            light.name, glm::length(light.edgeX),
                                            glm::length(light.edgeY), vecString(light.direction)));
            addAreaLightQuad(light, scene);
            continue;
        }
        const std::string emitterName =
            match->sphere ? scene.spheres[match->index].name : scene.meshes[match->index].name;
        const char* emitterKind = match->sphere ? "sphere" : "mesh";
        warnings.addExample(
            "area-merged",
            fmt::format("area light '{}' and emissive {} '{}' ({:.3g} m apart) describe one lamp; "
                        "the {} emits, the area light is dropped",
                        light.name, emitterKind, emitterName, best, emitterKind));
        uint32_t& materialIndexRef = match->sphere ? scene.spheres[match->index].material
                                                   : scene.meshes[match->index].material;
        const glm::vec3 meshRadiance = scene.materials[materialIndexRef].emission;
        const glm::vec3 difference = glm::abs(meshRadiance - light.radiance);
        const glm::vec3 scale = glm::max(meshRadiance, light.radiance);
        if (glm::any(glm::greaterThan(difference, 1e-3f * scale))) {
            // See scotty3d_policy.h: the area light's value lit Scotty3D's images.
            warnings.addExample("area-radiance",
                                fmt::format("area light '{}' radiance {} and lamp '{}' radiance {} "
                                            "disagree; using the area light's",
                                            light.name, vecString(light.radiance), emitterName,
                                            vecString(meshRadiance)));
            Material copy = scene.materials[materialIndexRef];
            copy.name += " (area light radiance)";
            copy.emission = light.radiance;
            materialIndexRef = static_cast<uint32_t>(scene.materials.size());
            scene.materials.push_back(copy);
        }
        if (!match->sphere && glm::dot(match->normal, light.direction) < 0) {
            Mesh& mesh = scene.meshes[match->index];
            for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
            for (glm::vec3& n : mesh.normals) n = -n;
            warnings.addExample("lamp-flipped",
                                fmt::format("lamp mesh '{}' faced away from area light '{}'; "
                                            "turned to face {}",
                                            mesh.name, light.name, vecString(light.direction)));
        }
    }

    // ---- point and spot lights ---------------------------------------------
    const std::vector<Emitter> all = emitters(scene);
    for (const Scotty3dPointLight& light : lights.pointLights) {
        const Emitter* match = nullptr;
        float best = std::numeric_limits<float>::max();
        for (const Emitter& e : all) {
            const float distance = glm::length(e.center - light.position);
            if (distance <= 0.1f * e.size && distance < best) {
                best = distance;
                match = &e;
            }
        }
        if (match && !light.spot) {
            const char* emitterKind = match->sphere ? "sphere" : "mesh";
            warnings.addExample(
                "point-merged",
                fmt::format("point light '{}' is {:.3g} m from the centre of emissive {} '{}': the "
                            "same lamp; dropped, the {} emits",
                            light.name, best, emitterKind,
                            match->sphere ? scene.spheres[match->index].name
                                          : scene.meshes[match->index].name,
                            emitterKind));
            continue;
        }
        // Scotty3D: irradiance colour x cos at any distance. Physical: I / d^2.
        const float d = glm::length(sceneCenter - light.position);
        const float d2 = d > 1e-6f ? d * d : 1.0f;
        const glm::vec3 intensity = light.color * d2;
        warnings.addExample(
            light.spot ? "spot-falloff" : "point-falloff",
            fmt::format("{} light '{}': Scotty3D's has no falloff; converted to an inverse-square "
                        "light of intensity {} W/sr (colour x d^2, d = {:.3g} m to the scene "
                        "centre, where the irradiance matches)",
                        light.spot ? "spot" : "point", light.name, vecString(intensity), d));
        if (light.spot) {
            SpotLight spot = *light.spot;
            spot.position = light.position;
            spot.intensity = intensity;
            scene.spotLights.push_back(spot);
        } else {
            scene.pointLights.push_back({light.position, intensity});
        }
    }

    if (lights.ambient) {
        Environment environment;
        environment.color = *lights.ambient;
        scene.environment = environment;
    }
}

void frameScotty3dCamera(const std::optional<glm::dmat4>& cameraWorld, const glm::vec3& boundsMin,
                         const glm::vec3& boundsMax, Camera& camera) {
    glm::dvec3 d(0, 0, 1);  // no camera: look down -Z from +Z
    if (cameraWorld) {
        // Step 2: the view direction transformed as a point, translation
        // included (M already holds step 1's Z_UP turn).
        const glm::dvec3 point(*cameraWorld * glm::dvec4(0, 0, -1, 1));
        const glm::dvec3 back = -(glm::dmat3(*cameraWorld) * glm::dvec3(0, 0, -1));
        if (glm::length(point) > 0)
            d = glm::normalize(point);
        else if (glm::length(back) > 0)
            d = glm::normalize(back);  // M(0,0,-1,1) at the origin: no direction to keep
    }
    // Step 3.
    const double phi = std::acos(std::clamp(d.y, -1.0, 1.0));
    const double theta = std::atan2(d.x, d.z);
    // Step 4: lights excluded (the caller's bounds hold meshes and spheres).
    const glm::dvec3 target = (glm::dvec3(boundsMin) + glm::dvec3(boundsMax)) * 0.5;
    const double r = 1.5 * glm::length(glm::dvec3(boundsMax) - glm::dvec3(boundsMin));
    // Step 5.
    const double sinPhi = std::sin(phi);
    camera.target = glm::vec3(target);
    camera.position = glm::vec3(
        target + r * glm::dvec3(sinPhi * std::sin(theta), std::cos(phi), sinPhi * std::cos(theta)));
    camera.up = sinPhi < 0 ? glm::vec3(0, -1, 0) : glm::vec3(0, 1, 0);
    if (std::abs(sinPhi) < 1e-6) {
        // Straight above or below: the rule's up is parallel to the view
        // direction (SOURCE.md leaves this open); take -Z / +Z as up.
        camera.up = glm::vec3(0, 0, d.y > 0 ? -1 : 1);
    }
}

}  // namespace vkpath::scene
