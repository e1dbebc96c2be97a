// glTF 2.0 import, in phases, each in a file of its own:
//   1-3. gltf_container: the file, the GLB container, the URI guard and
//        tinygltf's model;
//   4.   this file: the node hierarchy in world space, with the meshes
//        (gltf_meshes, through the range-checked gltf_accessors), materials
//        (gltf_materials), spheres, lights, the camera and the environment.
#include "scene/gltf_loader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "input_error.h"
#include "scene/environment.h"
#include "scene/gltf_accessors.h"
#include "scene/gltf_container.h"
#include "scene/gltf_materials.h"
#include "scene/gltf_meshes.h"
#include "scene/gltf_variants.h"
#include "scene/import_warnings.h"
#include "scene/load.h"

namespace vkpath::scene {
namespace {

namespace fs = std::filesystem;

constexpr double DEFAULT_CAMERA_FOV_DEGREES = 40.0;

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

struct CameraCandidate {
    int node;
    int camera;
    glm::dmat4 world;
};

class Importer {
  public:
    Importer(std::string file, const gltf::Document& document, const LoadOptions& options)
        : m_file(std::move(file)),
          m_folder(document.folder),
          m_model(document.model),
          m_options(options),
          m_warnings(m_file),
          m_accessors(document.model, m_file),
          m_textures(document, m_file, m_scene, m_warnings) {}

    Scene run() {
        checkExtensions();
        for (size_t i = 0; i < m_model.materials.size(); ++i)
            m_scene.materials.push_back(
                gltf::convertMaterial(m_model.materials[i], i, m_file, m_textures, m_warnings));
        if (!m_model.animations.empty())
            m_warnings.addCounted("animations are ignored: the scene is loaded at rest",
                                  "animation", m_model.animations[0].name);

        const std::vector<Visit> visits = traverse();
        chooseInstancedMeshes(visits);
        if (m_options.admit) m_options.admit(m_file, countGeometry(visits));
        for (const Visit& visit : visits) visitNode(visit.node, visit.world);

        if (m_scene.meshes.empty() && m_scene.spheres.empty())
            fail("no geometry: the scene has no triangles and no spheres");
        chooseCamera();
        readEnvironment();
        m_warnings.report();
        return std::move(m_scene);
    }

  private:
    struct Visit {
        int node;
        glm::dmat4 world;
    };

    template <typename... Args>
    [[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) const {
        throw InputError(
            fmt::format("{}: {}", m_file, fmt::format(format, std::forward<Args>(args)...)));
    }

    std::string nodeName(int index) const {
        const std::string& name = m_model.nodes[size_t(index)].name;
        return name.empty() ? fmt::format("node {}", index) : fmt::format("node '{}'", name);
    }

    // ---- extensions --------------------------------------------------------

    void checkExtensions() {
        std::set<std::string> used(m_model.extensionsUsed.begin(), m_model.extensionsUsed.end());
        auto collect = [&](const tinygltf::ExtensionMap& map) {
            for (const auto& entry : map) used.insert(entry.first);
        };
        collect(m_model.extensions);
        for (const auto& m : m_model.materials) {
            collect(m.extensions);
            collect(m.pbrMetallicRoughness.extensions);
        }
        for (const auto& n : m_model.nodes) collect(n.extensions);
        for (const auto& m : m_model.meshes)
            for (const auto& p : m.primitives) collect(p.extensions);
        for (const auto& c : m_model.cameras) collect(c.extensions);
        for (const auto& t : m_model.textures) collect(t.extensions);
        for (const std::string& name : used)
            if (!gltf::extensionSupported(name))
                m_warnings.addCounted(
                    fmt::format("extension '{}' is not supported and is ignored", name));
    }

    // ---- the environment ------------------------------------------------------

    // VKPATH_environment (docs/SCENES.md), on the glTF root: the light from
    // infinitely far away, so that a scene file carries its sky. Either an
    // equirectangular map `uri` (relative to the scene's folder, inside it) or
    // a constant `color`, times `strength`, turned `rotation` degrees about +Y.
    void readEnvironment() {
        const auto it = m_model.extensions.find("VKPATH_environment");
        if (it == m_model.extensions.end()) return;
        const tinygltf::Value& ext = it->second;
        const std::string what = "VKPATH_environment";
        if (!ext.IsObject()) fail("{} is not an object", what);
        auto number = [&](const char* key, double fallback) {
            if (!ext.Has(key)) return fallback;
            const tinygltf::Value& value = ext.Get(key);
            if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
                fail("{}: '{}' is not a finite number", what, key);
            return value.GetNumberAsDouble();
        };
        Environment env;
        env.strength = float(number("strength", 1.0));
        if (!(env.strength >= 0.0f)) fail("{}: strength {} is negative", what, env.strength);
        env.rotationDegrees = float(number("rotation", 0.0));
        if (ext.Has("uri") == ext.Has("color"))
            fail("{} needs exactly one of 'uri' and 'color'", what);
        if (ext.Has("uri")) {
            const tinygltf::Value& uri = ext.Get("uri");
            if (!uri.IsString()) fail("{}: uri is not a string", what);
            const std::string problem = gltf::uriProblem(uri.Get<std::string>(), m_folder);
            if (!problem.empty()) fail("{}: uri '{}' {}", what, uri.Get<std::string>(), problem);
            const fs::path mapPath = m_folder / gltf::decodeUri(uri.Get<std::string>());
            env.map = loadEnvironmentMap(mapPath);
            m_scene.referencedFiles.push_back(mapPath);
        } else {
            const tinygltf::Value& color = ext.Get("color");
            if (!color.IsArray() || color.ArrayLen() != 3)
                fail("{}: color is not an array of 3 numbers", what);
            for (int c = 0; c < 3; ++c) {
                const tinygltf::Value& v = color.Get(c);
                if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()) ||
                    v.GetNumberAsDouble() < 0.0)
                    fail("{}: color is not 3 finite numbers >= 0", what);
                env.color[c] = float(v.GetNumberAsDouble());
            }
        }
        m_scene.environment = std::move(env);
    }

    uint32_t defaultMaterial() {
        if (!m_defaultMaterial) {
            Material m;
            m.name = "default";  // grey Lambertian (albedo 0.8) for primitives without a material
            m_scene.materials.push_back(m);
            m_defaultMaterial = uint32_t(m_scene.materials.size() - 1);
        }
        return *m_defaultMaterial;
    }

    // ---- node hierarchy ------------------------------------------------------

    glm::dmat4 localMatrix(int index) const {
        const tinygltf::Node& node = m_model.nodes[size_t(index)];
        auto check = [&](const std::vector<double>& values, size_t size, const char* what) {
            if (!values.empty() && values.size() != size)
                fail("{}: {} needs {} numbers", nodeName(index), what, size);
            for (double v : values)
                if (!std::isfinite(v)) fail("{}: {} is not finite", nodeName(index), what);
        };
        check(node.matrix, 16, "matrix");
        check(node.translation, 3, "translation");
        check(node.rotation, 4, "rotation");
        check(node.scale, 3, "scale");
        if (!node.matrix.empty())
            return glm::make_mat4(node.matrix.data());  // column-major, as in glTF
        glm::dmat4 t(1.0), r(1.0), s(1.0);
        if (!node.translation.empty())
            t[3] = glm::dvec4(glm::make_vec3(node.translation.data()), 1.0);
        if (!node.rotation.empty()) {
            const auto& q = node.rotation;  // glTF order: x, y, z, w
            const glm::dquat quat(q[3], q[0], q[1], q[2]);
            if (!(glm::length(quat) > 0.0))
                fail("{}: rotation is a zero quaternion", nodeName(index));
            r = glm::mat4_cast(glm::normalize(quat));
        }
        if (!node.scale.empty()) {
            s[0][0] = node.scale[0];
            s[1][1] = node.scale[1];
            s[2][2] = node.scale[2];
        }
        return t * r * s;
    }

    // Depth-first, children in the order listed: "node order" for cameras.
    // glTF nodes form trees (at most one parent each) whose roots are the
    // scene's nodes; checking that first makes cycles unreachable.
    std::vector<Visit> traverse() {
        const size_t count = m_model.nodes.size();
        std::vector<int> parents(count, 0);
        for (size_t i = 0; i < count; ++i)
            for (int child : m_model.nodes[i].children) {
                if (child < 0 || size_t(child) >= count)
                    fail("{}: child {} does not exist", nodeName(int(i)), child);
                if (++parents[size_t(child)] > 1)
                    fail("{} has more than one parent", nodeName(child));
            }

        std::vector<int> roots;
        if (!m_model.scenes.empty()) {
            const int sceneIndex = m_model.defaultScene >= 0 ? m_model.defaultScene : 0;
            if (size_t(sceneIndex) >= m_model.scenes.size())
                fail("default scene {} does not exist", sceneIndex);
            if (m_model.scenes.size() > 1)
                m_warnings.addCounted(fmt::format("the file has {} scenes; only scene {} is loaded",
                                                  m_model.scenes.size(), sceneIndex));
            roots = m_model.scenes[size_t(sceneIndex)].nodes;
            std::vector<bool> seen(count, false);
            for (int root : roots) {
                if (root < 0 || size_t(root) >= count) fail("scene node {} does not exist", root);
                if (parents[size_t(root)] != 0)
                    fail("scene node {} is not a root: it has a parent", root);
                if (seen[size_t(root)]) fail("scene lists node {} twice", root);
                seen[size_t(root)] = true;
            }
        } else {
            for (size_t i = 0; i < count; ++i)
                if (parents[i] == 0) roots.push_back(int(i));
        }

        std::vector<Visit> order;
        std::vector<Visit> stack;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it)
            stack.push_back({*it, glm::dmat4(1.0)});
        while (!stack.empty()) {
            const Visit top = stack.back();
            stack.pop_back();
            const glm::dmat4 world = top.world * localMatrix(top.node);
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    if (!(std::abs(world[c][r]) <= double(std::numeric_limits<float>::max())))
                        fail("{}: its world transform is not finite as 32-bit floats",
                             nodeName(top.node));
            order.push_back({top.node, world});
            const auto& children = m_model.nodes[size_t(top.node)].children;
            for (auto it = children.rbegin(); it != children.rend(); ++it)
                stack.push_back({*it, world});
        }
        return order;
    }

    // Which glTF meshes are kept once and placed by instances
    // (LoadOptions::instancing): those several nodes place, whose primitives
    // emit no light, whose copies would add enough triangles.
    void chooseInstancedMeshes(const std::vector<Visit>& visits) {
        std::map<int, uint64_t> placements;
        for (const Visit& visit : visits)
            if (const int mesh = m_model.nodes[size_t(visit.node)].mesh; mesh >= 0)
                ++placements[mesh];
        for (const auto& [mesh, count] : placements) {
            if (count < 2 || m_options.instancing == Instancing::Off) continue;
            if (size_t(mesh) >= m_model.meshes.size()) continue;  // addMesh says what is wrong
            bool emissive = false;
            for (const tinygltf::Primitive& p : m_model.meshes[size_t(mesh)].primitives)
                emissive |= p.material >= 0 && size_t(p.material) < m_scene.materials.size() &&
                            m_scene.materials[size_t(p.material)].emissive();
            const uint64_t copies = (count - 1) * gltf::countMesh(m_model, mesh).triangles;
            if (!emissive &&
                (m_options.instancing == Instancing::On || copies >= INSTANCING_MIN_TRIANGLES))
                m_instanced[mesh] = std::nullopt;  // converted at its first placement
        }
    }

    // The geometry the visits will add: a mesh counted once per node that
    // places it, an instanced mesh once and an instance per node.
    GeometryCounts countGeometry(const std::vector<Visit>& visits) const {
        GeometryCounts counts;
        std::set<int> instanced;
        for (const Visit& visit : visits) {
            const tinygltf::Node& node = m_model.nodes[size_t(visit.node)];
            if (node.mesh >= 0 && m_instanced.contains(node.mesh)) {
                counts.instances += 1;
                if (instanced.insert(node.mesh).second)
                    counts += gltf::countMesh(m_model, node.mesh);
            } else if (node.mesh >= 0) {
                counts += gltf::countMesh(m_model, node.mesh);
            }
            if (node.extensions.contains("VKPATH_sphere")) counts.spheres += 1;
        }
        return counts;
    }

    void visitNode(int index, const glm::dmat4& world) {
        const tinygltf::Node& node = m_model.nodes[size_t(index)];
        if (!node.matrix.empty() &&
            (!node.translation.empty() || !node.rotation.empty() || !node.scale.empty()))
            m_warnings.addCounted("nodes with both a matrix and TRS use the matrix", "node",
                                  nodeName(index));
        if (node.skin >= 0)
            m_warnings.addCounted("skins are ignored: meshes are used as bound", "node",
                                  nodeName(index));
        if (node.mesh >= 0) addMesh(index, world);
        if (node.camera >= 0) {
            if (size_t(node.camera) >= m_model.cameras.size())
                fail("{}: camera {} does not exist", nodeName(index), node.camera);
            m_cameras.push_back({index, node.camera, world});
        }
        if (const auto it = node.extensions.find("KHR_lights_punctual");
            it != node.extensions.end())
            addLight(index, world, it->second);
        if (const auto it = node.extensions.find("VKPATH_sphere"); it != node.extensions.end())
            addSphere(index, world, it->second);
    }

    // ---- meshes --------------------------------------------------------------

    // A node's mesh: copied into world space, or, instanced, converted once
    // in its own space and placed by an instance.
    void addMesh(int nodeIndex, const glm::dmat4& world) {
        const int mesh = m_model.nodes[size_t(nodeIndex)].mesh;
        const auto instanced = m_instanced.find(mesh);
        if (instanced == m_instanced.end()) {
            appendMeshes(nodeIndex, world, false);
            return;
        }
        if (!instanced->second) instanced->second = appendMeshes(nodeIndex, glm::dmat4(1.0), true);
        const auto [first, count] = *instanced->second;
        if (count == 0) return;  // no triangle
        Instance instance;
        instance.name = nodeName(nodeIndex);
        instance.firstMesh = first;
        instance.meshCount = count;
        instance.objectToWorld = world;
        m_scene.instances.push_back(std::move(instance));
    }

    // Appends the primitives of node `nodeIndex`'s mesh under `world`;
    // returns the range of meshes they became.
    std::pair<uint32_t, uint32_t> appendMeshes(int nodeIndex, const glm::dmat4& world,
                                               bool instanced) {
        const auto first = uint32_t(m_scene.meshes.size());
        for (gltf::WorldPrimitive& primitive : gltf::convertMesh(
                 m_model, m_accessors, nodeIndex, nodeName(nodeIndex), world, m_file, m_warnings)) {
            if (primitive.usesDefaultMaterial) primitive.mesh.material = defaultMaterial();
            primitive.mesh.instanced = instanced;
            warnIfAnisotropyHasNoFrame(primitive.mesh);
            m_scene.meshes.push_back(std::move(primitive.mesh));
        }
        return {first, uint32_t(m_scene.meshes.size()) - first};
    }

    // KHR_materials_anisotropy turns its direction in the tangent frame, made
    // from texture coordinates (wavefront/surface_tables.cpp): a mesh without
    // them renders its material isotropic.
    void warnIfAnisotropyHasNoFrame(const Mesh& mesh) {
        const Material& material = m_scene.materials[mesh.material];
        if (material.anisotropy == 0.0f ||
            (materialKindInfo(material.kind).flags & VKP_KIND_MICROFACET) == 0)
            return;
        const TextureRef& frame =
            material.normalTexture.present() ? material.normalTexture : material.anisotropyTexture;
        const auto& uvs = frame.texCoord == 0 ? mesh.texcoords0 : mesh.texcoords1;
        if (uvs.size() != mesh.positions.size())
            m_warnings.addCounted(
                "anisotropic materials on meshes without texture coordinates render isotropic "
                "(the direction needs a tangent frame)",
                "mesh", mesh.name);
    }

    // ---- spheres ----------------------------------------------------------------

    void addSphere(int nodeIndex, const glm::dmat4& world, const tinygltf::Value& ext) {
        const std::string what = fmt::format("{}: VKPATH_sphere", nodeName(nodeIndex));
        if (!ext.IsObject()) fail("{} is not an object", what);
        const tinygltf::Value& radius = ext.Get("radius");
        if (!radius.IsNumber()) fail("{} needs a number 'radius'", what);
        const double r = radius.GetNumberAsDouble();
        if (!std::isfinite(r) || !(r > 0.0))
            fail("{}: radius {} is not a positive finite number", what, r);

        Sphere sphere;
        sphere.name = m_model.nodes[size_t(nodeIndex)].name;
        if (ext.Has("material")) {
            const tinygltf::Value& material = ext.Get("material");
            const double m = material.IsNumber() ? material.GetNumberAsDouble() : -1.0;
            if (m != std::floor(m) || m < 0.0 || m >= double(m_model.materials.size()))
                fail("{}: material is not the index of a material", what);
            sphere.material = uint32_t(m);
            // The traversal tests alpha on triangles only: a sphere has no
            // texture coordinates, and a BLEND sphere would need both of its
            // surfaces tested apart.
            if (m_scene.materials[sphere.material].alphaMode != AlphaMode::Opaque)
                m_warnings.addCounted("alphaMode is ignored on VKPATH_sphere: spheres are opaque",
                                      "sphere",
                                      sphere.name.empty() ? nodeName(nodeIndex) : sphere.name);
        } else {
            sphere.material = defaultMaterial();
        }
        const glm::dvec3 scales(glm::length(world[0]), glm::length(world[1]),
                                glm::length(world[2]));
        if (!finite(scales) || !(std::min({scales.x, scales.y, scales.z}) > 0.0))
            fail("{}: the node transform is singular", what);
        if (std::max({scales.x, scales.y, scales.z}) >
            std::min({scales.x, scales.y, scales.z}) * (1.0 + 1e-4))
            m_warnings.addCounted(
                "spheres under a non-uniform scale keep their shape: the radius is scaled by the "
                "geometric mean",
                "sphere", sphere.name.empty() ? nodeName(nodeIndex) : sphere.name);
        const glm::dvec3 centre(world[3]);
        const double worldRadius = r * std::cbrt(scales.x * scales.y * scales.z);
        if (!finite(centre) || !std::isfinite(float(worldRadius)))
            fail("{}: not finite after the transform", what);
        sphere.center = glm::vec3(centre);
        sphere.radius = float(worldRadius);
        m_scene.spheres.push_back(sphere);
    }

    // ---- lights ----------------------------------------------------------------

    void addLight(int nodeIndex, const glm::dmat4& world, const tinygltf::Value& ext) {
        const std::string what = fmt::format("{}: KHR_lights_punctual", nodeName(nodeIndex));
        if (!ext.IsObject() || !ext.Get("light").IsInt()) fail("{} needs an integer 'light'", what);
        const int index = ext.Get("light").Get<int>();
        if (index < 0 || size_t(index) >= m_model.lights.size())
            fail("{}: light {} does not exist", what, index);
        const tinygltf::Light& light = m_model.lights[size_t(index)];
        const std::string name = light.name.empty() ? fmt::format("light {}", index) : light.name;

        glm::dvec3 color(1.0);
        if (!light.color.empty()) {
            if (light.color.size() != 3) fail("light '{}': color needs 3 numbers", name);
            color = glm::make_vec3(light.color.data());
        }
        if (!finite(color) || color.x < 0 || color.y < 0 || color.z < 0)
            fail("light '{}': color is not finite and non-negative", name);
        if (!std::isfinite(light.intensity) || light.intensity < 0)
            fail("light '{}': intensity {} is not finite and non-negative", name, light.intensity);
        // (tinygltf reads an absent range as 0: infinite)
        if (!std::isfinite(light.range) || light.range < 0.0)
            fail("light '{}': range {} is not > 0", name, light.range);
        if (light.range > 0.0 && light.type == "directional")
            fail("light '{}': a directional light has no range", name);
        const float range = float(light.range);
        // Photometric units taken as radiometric (docs/SCENES.md): cd as W/sr, lx as W/m^2.
        const glm::vec3 radiometric(color * light.intensity);
        const glm::vec3 position(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
        const glm::dvec3 axis =
            glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);  // lights point along their -Z
        if (!finite(glm::dvec3(position)) || !(glm::length(axis) > 0.0) || !finite(axis))
            fail("light '{}': the node transform is singular or not finite", name);
        const glm::vec3 direction(glm::normalize(axis));

        if (light.type == "point") {
            m_scene.pointLights.push_back({position, radiometric, range});
        } else if (light.type == "spot") {
            const double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
            if (!(inner >= 0.0 && inner < outer && outer <= glm::half_pi<double>()))
                fail(
                    "light '{}': cone angles inner {} and outer {} need 0 <= inner < outer <= pi/2",
                    name, inner, outer);
            m_scene.spotLights.push_back(
                {position, direction, radiometric, float(inner), float(outer), range});
        } else if (light.type == "directional") {
            m_scene.directionalLights.push_back({direction, radiometric});
        } else {
            fail("light '{}': unknown type '{}'", name, light.type);
        }
    }

    // ---- camera ------------------------------------------------------------------

    void chooseCamera() {
        const CameraCandidate* chosen = nullptr;
        if (!m_options.cameraName.empty()) {
            std::vector<std::string> names;
            for (const CameraCandidate& c : m_cameras) {
                const std::string& cameraName = m_model.cameras[size_t(c.camera)].name;
                const std::string& nodeName = m_model.nodes[size_t(c.node)].name;
                if (cameraName == m_options.cameraName || nodeName == m_options.cameraName) {
                    chosen = &c;
                    break;
                }
                names.push_back("'" + (cameraName.empty() ? nodeName : cameraName) + "'");
            }
            if (!chosen)
                fail("no camera named '{}' (the scene has {})", m_options.cameraName,
                     names.empty() ? std::string("none")
                                   : fmt::format("{}", fmt::join(names, ", ")));
            if (m_model.cameras[size_t(chosen->camera)].type != "perspective")
                fail("camera '{}' is {}; only perspective cameras are supported",
                     m_options.cameraName, m_model.cameras[size_t(chosen->camera)].type);
        } else {
            for (const CameraCandidate& c : m_cameras) {
                if (m_model.cameras[size_t(c.camera)].type == "perspective") {
                    chosen = &c;
                    break;
                }
                m_warnings.addCounted("orthographic cameras are not supported and are skipped",
                                      "camera", m_model.cameras[size_t(c.camera)].name);
            }
        }
        if (!chosen) {
            m_scene.camera = frameBoundingBox();
            m_warnings.addCounted(
                "no perspective camera: a default camera frames the scene from +Z");
            return;
        }

        const tinygltf::Camera& gltf = m_model.cameras[size_t(chosen->camera)];
        Camera camera;
        camera.name = !gltf.name.empty() ? gltf.name : m_model.nodes[size_t(chosen->node)].name;
        const double yfov = gltf.perspective.yfov, aspect = gltf.perspective.aspectRatio;
        if (!(yfov > 0.0 && yfov < glm::pi<double>()))
            fail("camera '{}': yfov {} is not in (0, pi) radians", camera.name, yfov);
        if (!(aspect >= 0.0) || !std::isfinite(aspect))
            fail("camera '{}': aspectRatio {} is not positive", camera.name, aspect);
        // yfov is vertical; the scene model's field of view is horizontal for
        // the camera's own aspect. Without an aspect, treat the camera as
        // square (see gltf_loader.h).
        const double a = aspect > 0.0 ? aspect : 1.0;
        camera.xfovDegrees = float(glm::degrees(2.0 * std::atan(a * std::tan(yfov / 2.0))));
        camera.aspect = float(a);

        const glm::dmat4& world = chosen->world;
        const glm::dvec3 forward = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
        const glm::dvec3 up = glm::dmat3(world) * glm::dvec3(0.0, 1.0, 0.0);
        if (!(glm::length(forward) > 0.0) || !(glm::length(glm::cross(forward, up)) > 0.0) ||
            !finite(forward) || !finite(up))
            fail("camera '{}': the node transform is singular", camera.name);
        camera.position = glm::vec3(world[3]);
        camera.target = glm::vec3(glm::dvec3(world[3]) + glm::normalize(forward));
        camera.up = glm::vec3(glm::normalize(up));
        m_scene.camera = camera;
    }

    // A camera on the +Z side (glTF's "front") of the scene's bounding sphere,
    // looking at its centre, 40 degrees wide on both axes (aspect 1: a film of
    // any shape widens its narrower axis, so the sphere is never cropped).
    // In double: the box's diagonal of geometry far apart (1e22 m) squares
    // past a float's range. A camera that still leaves it is refused.
    Camera frameBoundingBox() const {
        const auto [lo, hi] = m_scene.geometryBounds();
        const glm::dvec3 centre = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
        const double radius = std::max(0.5 * glm::length(glm::dvec3(hi) - glm::dvec3(lo)), 1e-3);
        const double distance = radius / std::sin(glm::radians(DEFAULT_CAMERA_FOV_DEGREES) / 2.0);
        const glm::dvec3 position = centre + glm::dvec3(0.0, 0.0, distance);
        if (!(std::abs(position.z) <= double(std::numeric_limits<float>::max())))
            fail("no camera, and the geometry's bounds ({:g} m across) are too large to frame one",
                 2.0 * radius);
        Camera camera;
        camera.name = "default";
        camera.position = glm::vec3(position);
        camera.target = glm::vec3(centre);
        camera.up = {0.0f, 1.0f, 0.0f};
        camera.xfovDegrees = float(DEFAULT_CAMERA_FOV_DEGREES);
        camera.aspect = 1.0f;
        return camera;
    }

    std::string m_file;
    fs::path m_folder;  // the scene file's folder: external files must stay inside it
    const tinygltf::Model& m_model;
    const LoadOptions& m_options;
    ImportWarnings m_warnings;
    gltf::Accessors m_accessors;
    Scene m_scene;
    gltf::TextureImporter m_textures;
    std::optional<uint32_t> m_defaultMaterial;
    std::vector<CameraCandidate> m_cameras;  // in node order
    // The instanced glTF meshes, each with the range of Scene::meshes it
    // became once converted (at its first placement).
    std::map<int, std::optional<std::pair<uint32_t, uint32_t>>> m_instanced;
};

}  // namespace

Scene loadGltf(const std::filesystem::path& path, const LoadOptions& options) {
    gltf::Document document = gltf::readDocument(path);
    std::vector<std::string> variants =
        gltf::applyMaterialVariant(document.model, options.materialVariant, path.string());
    Scene scene = Importer(path.string(), document, options).run();
    scene.materialVariants = std::move(variants);
    scene.referencedFiles.insert(scene.referencedFiles.begin(), document.filesRead.begin(),
                                 document.filesRead.end());
    return scene;
}

}  // namespace vkpath::scene
