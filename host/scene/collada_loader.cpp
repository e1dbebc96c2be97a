// The Scotty3D COLLADA importer: the document and its node hierarchy.
//
// Reading: <library_visual_scenes> is walked from <scene><instance_visual_scene>;
// every node's transform is the product of its <matrix> (row-major),
// <translate>, <rotate>, <scale> and <lookat> elements in document order, and
// a root transform turns Z_UP / X_UP files to +Y up exactly as Scotty3D does
// (SOURCE.md: x' = -x, y' = z, z' = y for Z_UP) and applies <unit meter>.
// Geometry is instanced per node (a geometry used twice is parsed once,
// collada_geometry), after the hierarchy is walked and the scene's geometry
// counted (LoadOptions::admit): copied into world space per
// <instance_geometry>, or, where several bind it the same materials and
// LoadOptions::instancing says so, converted once in its own space and
// placed by scene::Instances; materials are bound per instance through <bind_material>
// symbols (collada_materials). Lights and the camera are gathered here and
// handed to the Scotty3D policy (scotty3d_policy.h), which decides what they
// become where Scotty3D is not physical.
//
// Decisions of the reader (each also prints a warning line when it applies):
//
// - Directional lights: colour is the irradiance in W/m^2, travelling along
//   M(0,0,-1) (the COLLADA convention; Scotty3D transforms the direction as a
//   point, translation included, which is a bug, not a choice).
// - Materials follow Scotty3D (collada_materials.h).
// - Normals: a per-corner NORMAL input is kept per vertex by splitting
//   vertices where a position has several normals. When every corner normal
//   of a primitive equals its face's normal (flat-shaded exports: the Cornell
//   boxes, the planes), the normals add nothing and are dropped so vertices
//   stay shared. Normals transform with the inverse transpose (computed as
//   the cofactor matrix, which also exists for the singular transforms some
//   of these files use); a negative determinant flips the winding.
// - A camera is framed by Scotty3D's rule (frameScotty3dCamera); its optics
//   are read here, and malformed optics are a warning with Scotty3D's 50
//   degree hFov, since Scotty3D renders from such a camera too.
#include "scene/collada_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include <optional>
#include <pugixml.hpp>
#include <set>
#include <string_view>

#include "input_error.h"
#include "scene/collada_document.h"
#include "scene/collada_geometry.h"
#include "scene/collada_materials.h"
#include "scene/import_warnings.h"
#include "scene/scotty3d_policy.h"

namespace vkpath::scene {
namespace {

using namespace collada;

// Caps so a broken or hostile file fails with a message instead of
// exhausting the stack (deep or cyclic node instancing).
constexpr int MAX_NODE_DEPTH = 256;
constexpr uint64_t MAX_NODE_VISITS = 1'000'000;

struct CameraInstance {
    std::string nodeName;
    pugi::xml_node camera;
    std::optional<glm::dmat4> world;  // none: its node's transform is malformed
};

// Whether `node` holds cameras and nothing its transform would place besides
// (no geometry, light or child node): Scotty3D keeps only a camera's direction.
bool holdsOnlyCameras(pugi::xml_node node) {
    bool camera = false;
    for (pugi::xml_node child : node.children()) {
        const std::string_view kind = child.name();
        if (kind == "instance_camera")
            camera = true;
        else if (kind == "node" || kind == "instance_node" || kind == "instance_geometry" ||
                 kind == "instance_light" || kind == "instance_controller")
            return false;
    }
    return camera;
}

// An <instance_geometry> met in the node hierarchy, built once the whole
// scene's geometry has been counted (LoadOptions::admit).
struct GeometryInstance {
    pugi::xml_node instance;
    pugi::xml_node geometry;
    glm::dmat4 world;
    std::string nodeName;
};

class ColladaLoader {
  public:
    ColladaLoader(const std::filesystem::path& path, const LoadOptions& options)
        : m_document(path),
          m_options(options),
          m_warnings(m_document.file()),
          m_geometry(m_document, m_warnings),
          m_materials(m_document, m_warnings, m_scene) {}

    Scene load(std::vector<std::string>* warningLines);

  private:
    [[noreturn]] void fail(const std::string& what) const { m_document.fail(what); }
    // An InputError's message without its "<file>: " prefix, to warn with.
    std::string withoutFile(const InputError& error) const {
        std::string reason = error.what();
        const std::string prefix = m_document.file() + ": ";
        if (reason.rfind(prefix, 0) == 0) reason.erase(0, prefix.size());
        return reason;
    }

    glm::dmat4 rootTransform();
    glm::dmat4 localTransform(pugi::xml_node node);
    void visitNode(pugi::xml_node node, const glm::dmat4& parent, int depth);
    // A mesh geometry with the materials an instance binds to it: what
    // instances of one geometry must share to share its meshes.
    using InstancedKey = std::pair<const void*, Bindings>;
    static InstancedKey instancedKey(const GeometryInstance& g);
    void chooseInstancedGeometry();
    GeometryCounts countGeometry();
    void addGeometryInstance(const GeometryInstance& instance);
    void addLightInstance(pugi::xml_node instance, const glm::dmat4& world,
                          const std::string& nodeName);
    std::optional<glm::dmat4> readCamera();

    Document m_document;
    LoadOptions m_options;
    ImportWarnings m_warnings;
    Scene m_scene;
    Geometry m_geometry;
    Materials m_materials;
    Scotty3dLights m_lights;
    std::vector<CameraInstance> m_cameras;
    std::vector<GeometryInstance> m_geometryInstances;  // in document order
    // The instanced geometries (LoadOptions::instancing), each with the range
    // of Scene::meshes it became once converted (at its first instance).
    std::map<InstancedKey, std::optional<std::pair<uint32_t, uint32_t>>> m_instanced;
    uint64_t m_nodeVisits = 0;
};

// ===========================================================================
// Node hierarchy
// ===========================================================================

glm::dmat4 ColladaLoader::rootTransform() {
    const pugi::xml_node asset = m_document.root().child("asset");
    glm::dmat4 root(1.0);
    const std::string up = asset.child("up_axis").child_value();
    std::string_view axis(up);
    auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (!axis.empty() && space(axis.front())) axis.remove_prefix(1);
    while (!axis.empty() && space(axis.back())) axis.remove_suffix(1);
    if (axis == "Z_UP") {
        // SOURCE.md step 1 (Scotty3D's ColladaParser): x' = -x, y' = z, z' = y.
        root = glm::dmat4(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, 1, 0, 0),
                          glm::dvec4(0, 0, 0, 1));
    } else if (axis == "X_UP") {
        // Scotty3D: swap x and y, negate z (a rotation, like the Z_UP one).
        root = glm::dmat4(glm::dvec4(0, 1, 0, 0), glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, -1, 0),
                          glm::dvec4(0, 0, 0, 1));
    } else if (!axis.empty() && axis != "Y_UP") {
        fail(fmt::format("<up_axis> '{}' is not X_UP, Y_UP or Z_UP", axis));
    }
    if (const pugi::xml_attribute meter = asset.child("unit").attribute("meter")) {
        double scale = 0;
        std::string text = meter.as_string();
        // Some exporters write the decimal comma of their locale ("0,01");
        // read it as a point, as Assimp and Blender do, and say so.
        if (!parseNumber(text, scale) && text.find(',') != std::string::npos &&
            text.find(',') == text.rfind(',') && text.find('.') == std::string::npos) {
            std::string pointed = text;
            pointed[pointed.find(',')] = '.';
            if (parseNumber(pointed, scale))
                m_warnings.addExample(
                    "unit comma", fmt::format("<unit meter=\"{}\"> has a decimal comma; read as {}",
                                              text, pointed));
        }
        if (!(scale > 0) || !std::isfinite(scale))
            fail(fmt::format("<unit meter=\"{}\"> is not a positive number", text));
        if (scale != 1.0) root = root * glm::scale(glm::dmat4(1.0), glm::dvec3(scale));
    }
    return root;
}

glm::dmat4 ColladaLoader::localTransform(pugi::xml_node node) {
    const std::string nodeName = fmt::format("node '{}'", nameOf(node));
    glm::dmat4 m(1.0);
    for (pugi::xml_node e : node.children()) {
        const std::string_view kind = e.name();
        auto values = [&](size_t n) {
            const std::string what = fmt::format("{}: <{}>", nodeName, kind);
            std::vector<double> v = m_document.numbers(e, what);
            if (v.size() != n) fail(fmt::format("{} has {} numbers, needs {}", what, v.size(), n));
            for (double x : v)
                if (!std::isfinite(x)) fail(fmt::format("{} has a non-finite number", what));
            return v;
        };
        if (kind == "matrix") {
            const std::vector<double> v = values(16);
            glm::dmat4 mat;
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) mat[c][r] = v[r * 4 + c];  // file is row-major
            m = m * mat;
        } else if (kind == "translate") {
            const std::vector<double> v = values(3);
            m = glm::translate(m, glm::dvec3(v[0], v[1], v[2]));
        } else if (kind == "rotate") {
            const std::vector<double> v = values(4);
            const glm::dvec3 axis(v[0], v[1], v[2]);
            if (glm::length(axis) == 0.0) {
                if (v[3] != 0.0) fail(fmt::format("{}: <rotate> has a zero axis", nodeName));
                continue;
            }
            m = glm::rotate(m, glm::radians(v[3]), axis);
        } else if (kind == "scale") {
            const std::vector<double> v = values(3);
            m = glm::scale(m, glm::dvec3(v[0], v[1], v[2]));
        } else if (kind == "lookat") {
            const std::vector<double> v = values(9);
            const glm::dvec3 eye(v[0], v[1], v[2]), at(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
            if (glm::length(glm::cross(at - eye, up)) == 0.0)
                fail(fmt::format("{}: <lookat> is degenerate", nodeName));
            m = m * glm::inverse(glm::lookAt(eye, at, up));
        } else if (kind == "skew") {
            // Not a transform Scotty3D reads either; warned rather than guessed.
            m_warnings.addExample(
                "skew",
                fmt::format("{}: <skew> transforms are not supported and are ignored", nodeName));
        }
    }
    return m;
}

void ColladaLoader::visitNode(pugi::xml_node node, const glm::dmat4& parent, int depth) {
    if (depth > MAX_NODE_DEPTH)
        fail(fmt::format("node hierarchy deeper than {} levels (cyclic <instance_node>?)",
                         MAX_NODE_DEPTH));
    if (++m_nodeVisits > MAX_NODE_VISITS)
        fail(fmt::format("more than {} node instances", MAX_NODE_VISITS));
    const std::string nodeName = nameOf(node);
    // Scotty3D reads a <matrix> as whatever numbers it holds and keeps only a
    // camera's direction: a camera node's malformed transform is a warning,
    // and the camera is placed as when there is none.
    glm::dmat4 local(1.0);
    bool placed = true;
    try {
        local = localTransform(node);
    } catch (const InputError& e) {
        if (!holdsOnlyCameras(node)) throw;
        m_warnings.addExample(
            "camera transform",
            fmt::format("{}; the camera is placed by Scotty3D's rule from +Z", withoutFile(e)));
        placed = false;
    }
    const glm::dmat4 world = parent * local;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!(std::abs(world[c][r]) <= double(std::numeric_limits<float>::max())))
                fail(fmt::format("node '{}': its world transform is not finite as 32-bit floats",
                                 nodeName));

    for (pugi::xml_node child : node.children()) {
        const std::string_view kind = child.name();
        const std::string context = fmt::format("node '{}'", nodeName);
        if (kind == "node") {
            visitNode(child, world, depth + 1);
        } else if (kind == "instance_node") {
            visitNode(
                m_document.resolve(child.attribute("url").as_string(nullptr), "node", context),
                world, depth + 1);
        } else if (kind == "instance_geometry") {
            m_geometryInstances.push_back(
                {child,
                 m_document.resolve(child.attribute("url").as_string(nullptr), "geometry", context),
                 world, nodeName});
        } else if (kind == "instance_camera") {
            // A camera that cannot be found is a warning, as in Scotty3D, which
            // places its camera from the scene's bounds.
            try {
                m_cameras.push_back({nodeName,
                                     m_document.resolve(child.attribute("url").as_string(nullptr),
                                                        "camera", context),
                                     placed ? std::optional(world) : std::nullopt});
            } catch (const InputError& e) {
                m_warnings.addExample("camera instance",
                                      fmt::format("{}; ignored", withoutFile(e)));
            }
        } else if (kind == "instance_light") {
            addLightInstance(child, world, nodeName);
        } else if (kind == "instance_controller") {
            m_warnings.addExample("controller",
                                  fmt::format("node '{}': <instance_controller> (skinning, "
                                              "morphing) is not supported; ignored",
                                              nodeName));
        }
    }
}

// ===========================================================================
// Geometry, lights and the camera
// ===========================================================================

Bindings bindingsOf(pugi::xml_node instance) {
    Bindings bindings;
    for (pugi::xml_node im :
         instance.child("bind_material").child("technique_common").children("instance_material"))
        bindings.emplace_back(im.attribute("symbol").as_string(),
                              im.attribute("target").as_string());
    return bindings;
}

uint64_t triangleCount(const LocalMesh& local) {
    uint64_t triangles = 0;
    for (const Primitive& primitive : local.primitives) triangles += primitive.corners.size() / 3;
    return triangles;
}

ColladaLoader::InstancedKey ColladaLoader::instancedKey(const GeometryInstance& g) {
    return {g.geometry.internal_object(), bindingsOf(g.instance)};
}

// Which <mesh> geometries are kept once and placed by instances
// (LoadOptions::instancing): those several <instance_geometry>s place with
// the same material bindings, whose materials emit no light, whose copies
// would add enough triangles (as the glTF importer decides).
void ColladaLoader::chooseInstancedGeometry() {
    if (m_options.instancing == Instancing::Off) return;
    std::map<InstancedKey, std::pair<uint64_t, const GeometryInstance*>> placements;
    for (const GeometryInstance& g : m_geometryInstances)
        if (g.geometry.child("mesh")) {
            auto& [count, first] = placements[instancedKey(g)];
            if (count++ == 0) first = &g;
        }
    for (const auto& [key, placed] : placements) {
        const auto [count, first] = placed;
        if (count < 2) continue;
        const LocalMesh& local = m_geometry.localMesh(first->geometry);
        if (m_options.instancing == Instancing::Auto &&
            (count - 1) * triangleCount(local) < INSTANCING_MIN_TRIANGLES)
            continue;
        bool emissive = false;
        for (const Primitive& primitive : local.primitives)
            emissive |=
                m_scene.materials
                    .at(m_materials.forSymbol(primitive.symbol, key.second, first->nodeName))
                    .emissive();
        if (!emissive) m_instanced[key] = std::nullopt;
    }
}

// The geometry the instances will add: each <mesh> geometry's triangles once
// per instance (an instanced one's once, and an instance each), with a vertex
// per corner (an upper bound: an instance splits a position only where its
// corners' normals differ).
GeometryCounts ColladaLoader::countGeometry() {
    GeometryCounts counts;
    std::set<InstancedKey> counted;
    for (const GeometryInstance& g : m_geometryInstances) {
        if (g.geometry.child("mesh")) {
            if (!m_instanced.empty()) {
                const InstancedKey key = instancedKey(g);
                if (m_instanced.contains(key)) {
                    counts.instances += 1;
                    if (!counted.insert(key).second) continue;
                }
            }
            const LocalMesh& local = m_geometry.localMesh(g.geometry);
            for (const Primitive& primitive : local.primitives) {
                const uint64_t corners = primitive.corners.size();
                counts.triangles += corners / 3;
                counts.vertices += corners;
                if (!primitive.corners.empty() && primitive.corners[0].normal != NO_INDEX)
                    counts.normals += corners;
                if (!primitive.corners.empty() && primitive.corners[0].texCoord != NO_INDEX)
                    counts.texcoords += corners;
            }
        } else if (cmuTechnique(g.geometry).child("sphere")) {
            counts.spheres += 1;
        }
    }
    return counts;
}

void ColladaLoader::addGeometryInstance(const GeometryInstance& g) {
    const pugi::xml_node instance = g.instance, geometry = g.geometry;
    const glm::dmat4& world = g.world;
    const std::string& nodeName = g.nodeName;
    const Bindings bindings = bindingsOf(instance);

    // Scotty3D's order: a <mesh> makes a mesh, else the CMU462 <sphere>.
    if (geometry.child("mesh")) {
        auto materialFor = [&](const std::string& symbol) {
            return m_materials.forSymbol(symbol, bindings, nodeName);
        };
        const auto instanced =
            m_instanced.empty() ? m_instanced.end() : m_instanced.find(instancedKey(g));
        if (instanced == m_instanced.end()) {
            m_geometry.addMeshInstance(m_geometry.localMesh(geometry), world, nodeName, materialFor,
                                       m_scene.meshes);
            return;
        }
        // Instanced: converted once in its own space, then placed.
        if (!instanced->second) {
            const auto first = uint32_t(m_scene.meshes.size());
            m_geometry.addMeshInstance(m_geometry.localMesh(geometry), glm::dmat4(1.0),
                                       nameOf(geometry), materialFor, m_scene.meshes);
            for (size_t i = first; i < m_scene.meshes.size(); ++i)
                m_scene.meshes[i].instanced = true;
            instanced->second = {first, uint32_t(m_scene.meshes.size()) - first};
        }
        const auto [first, count] = *instanced->second;
        if (count > 0) m_scene.instances.push_back({nodeName, first, count, world});
        return;
    }
    if (const pugi::xml_node sphere = cmuTechnique(geometry).child("sphere")) {
        const std::string what = fmt::format("geometry '{}': sphere", nameOf(geometry));
        const double radius = m_document.scalar(sphere.child("radius"), what + " <radius>");
        if (!(radius > 0)) fail(fmt::format("{} radius {} is not positive", what, radius));
        if (std::optional<Sphere> s = m_geometry.sphereInstance(radius, world, nodeName)) {
            // A sphere has no primitive symbol; Scotty3D takes the first binding.
            s->material = m_materials.forSymbol("", bindings, nodeName);
            m_scene.spheres.push_back(*s);
        }
        return;
    }
    m_warnings.addExample("geometry-kind",
                          fmt::format("geometry '{}' has neither a <mesh> nor a CMU462 <sphere> "
                                      "(splines, convex meshes are not supported); ignored",
                                      nameOf(geometry)));
}

void ColladaLoader::addLightInstance(pugi::xml_node instance, const glm::dmat4& world,
                                     const std::string& nodeName) {
    const pugi::xml_node light = m_document.resolve(instance.attribute("url").as_string(nullptr),
                                                    "light", fmt::format("node '{}'", nodeName));
    const std::string name = nameOf(light);
    const std::string what = fmt::format("light '{}'", name);
    // Scotty3D reads the CMU462 technique when there is one (CBspheres'
    // lamp is a COLLADA <point> and a CMU462 <area>: it is an area light).
    pugi::xml_node type = cmuTechnique(light).first_child();
    while (type && type.type() != pugi::node_element) type = type.next_sibling();
    if (!type) {
        type = light.child("technique_common").first_child();
        while (type && type.type() != pugi::node_element) type = type.next_sibling();
    }
    if (!type) {
        m_warnings.addExample("light-empty", fmt::format("{} has no light type; ignored", what));
        return;
    }
    const std::string_view kind = type.name();
    const glm::dmat3 linear(world);
    const glm::vec3 position(world * glm::dvec4(0, 0, 0, 1));
    const glm::vec3 forward(linear * glm::dvec3(0, 0, -1));  // COLLADA lights point down -Z
    auto lightColor = [&] {
        return m_document.color(type.child("color"), fmt::format("{} <color>", what));
    };

    if (kind == "area") {
        Scotty3dAreaLight area{name,
                               position,
                               glm::vec3(linear * glm::dvec3(-1, 0, 0)),
                               glm::vec3(linear * glm::dvec3(0, 1, 0)),
                               forward,
                               lightColor()};
        const float length = glm::length(forward);
        if (!(glm::length(glm::cross(area.edgeX, area.edgeY)) > 0) || !(length > 0) ||
            !allFinite(area.center)) {
            m_warnings.addExample("light-degenerate",
                                  fmt::format("{}: zero-size area light dropped", what));
            return;
        }
        area.direction = forward / length;
        m_lights.areaLights.push_back(area);
    } else if (kind == "point" || kind == "spot") {
        Scotty3dPointLight point{name, position, lightColor(), std::nullopt};
        if (kind == "spot") {
            const float length = glm::length(forward);
            if (!(length > 0)) {
                m_warnings.addExample(
                    "light-degenerate",
                    fmt::format("{}: spot light without a direction dropped", what));
                return;
            }
            SpotLight spot;
            spot.direction = forward / length;
            // falloff_angle is the cone's full angle (Blender's spot size);
            // falloff_exponent (Blender's blend) sets the soft edge.
            double falloff = 180.0, blend = 0.15;
            if (type.child("falloff_angle"))
                falloff = m_document.scalar(type.child("falloff_angle"), what + " <falloff_angle>");
            if (type.child("falloff_exponent"))
                blend =
                    m_document.scalar(type.child("falloff_exponent"), what + " <falloff_exponent>");
            if (!(falloff > 0 && falloff <= 360))
                fail(fmt::format("{}: falloff_angle {} is not in (0, 360]", what, falloff));
            spot.outerConeAngle = static_cast<float>(glm::radians(std::min(falloff, 180.0)) / 2);
            spot.innerConeAngle =
                static_cast<float>(spot.outerConeAngle * (1.0 - std::clamp(blend, 0.0, 1.0)));
            point.spot = spot;
            m_warnings.addExample("spot",
                                  fmt::format("{}: spot light approximated (Scotty3D does not "
                                              "render spot lights; cone from falloff_angle)",
                                              what));
        }
        m_lights.pointLights.push_back(point);
    } else if (kind == "directional") {
        const float length = glm::length(forward);
        if (!(length > 0)) {
            m_warnings.addExample(
                "light-degenerate",
                fmt::format("{}: directional light without a direction dropped", what));
            return;
        }
        m_scene.directionalLights.push_back({forward / length, lightColor()});
    } else if (kind == "ambient") {
        m_lights.ambient = m_lights.ambient.value_or(glm::vec3(0.0f)) + lightColor();
        m_warnings.addExample("ambient",
                              fmt::format("{}: Scotty3D's ambient light is a +Y hemisphere "
                                          "for direct lighting only, invisible to the camera; "
                                          "vkpath uses a constant environment of the same "
                                          "radiance over the whole sphere",
                                          what));
    } else {
        m_warnings.addExample(
            "light-type", fmt::format("{}: light type <{}> is not supported; ignored", what, kind));
    }
}

// The optics of the camera options.cameraName names (else the first); the
// world matrix of its node, for the framing, or none without a camera.
std::optional<glm::dmat4> ColladaLoader::readCamera() {
    Camera& camera = m_scene.camera;
    if (m_cameras.empty()) {
        m_warnings.addExample("no-camera",
                              "no camera; framing the scene from +Z with a 50 degree fov");
        camera.name = "default";
        camera.xfovDegrees = 50.0f;  // Scotty3D's default hFov
    } else {
        const CameraInstance* chosen = &m_cameras.front();
        if (!m_options.cameraName.empty()) {
            chosen = nullptr;
            std::string names;
            for (const CameraInstance& c : m_cameras) {
                const std::string& wanted = m_options.cameraName;
                if (c.nodeName == wanted || nameOf(c.camera) == wanted ||
                    c.camera.attribute("id").as_string() == wanted)
                    chosen = chosen ? chosen : &c;
                names += (names.empty() ? "" : ", ") + c.nodeName;
            }
            if (!chosen)
                fail(
                    fmt::format("no camera named '{}' (cameras: {})", m_options.cameraName, names));
        }
        const std::string what = fmt::format("camera '{}'", nameOf(chosen->camera));
        camera.name = chosen->nodeName;
        // Scotty3D frames the scene itself and reads little of the camera
        // (SOURCE.md), so a camera it would render from is not refused for
        // malformed optics: a warning, and Scotty3D's 50 degree hFov.
        try {
            const pugi::xml_node optics = chosen->camera.child("optics").child("technique_common");
            const pugi::xml_node perspective = optics.child("perspective");
            if (!perspective) {
                if (!optics.child("orthographic")) fail(what + " has no <perspective>");
                m_warnings.addExample(
                    "orthographic",
                    what + ": orthographic camera approximated by a 50 degree perspective");
                camera.xfovDegrees = 50.0f;
            } else {
                double aspect = 0;
                if (perspective.child("aspect_ratio")) {
                    aspect = m_document.scalar(perspective.child("aspect_ratio"),
                                               what + " <aspect_ratio>");
                    if (!(aspect > 0))
                        fail(fmt::format("{}: aspect_ratio {} is not positive", what, aspect));
                }
                double xfov = 0;
                if (perspective.child("xfov")) {
                    xfov = m_document.scalar(perspective.child("xfov"), what + " <xfov>");
                } else if (perspective.child("yfov")) {
                    const double yfov =
                        m_document.scalar(perspective.child("yfov"), what + " <yfov>");
                    if (!(yfov > 0 && yfov < 180))
                        fail(fmt::format("{}: yfov {} is not in (0, 180) degrees", what, yfov));
                    // SOURCE.md: yfov = 2 atan(tan(xfov / 2) / aspect), inverted.
                    xfov = glm::degrees(2.0 * std::atan(std::tan(glm::radians(yfov) / 2) *
                                                        (aspect > 0 ? aspect : 1.0)));
                } else {
                    fail(what + " has neither <xfov> nor <yfov>");
                }
                if (!(xfov > 0 && xfov < 180))
                    fail(fmt::format("{}: xfov {} is not in (0, 180) degrees", what, xfov));
                camera.xfovDegrees = static_cast<float>(xfov);
                camera.aspect = static_cast<float>(aspect);
            }
        } catch (const InputError& e) {
            m_warnings.addExample("camera optics",
                                  fmt::format("{}; the camera keeps its direction with Scotty3D's "
                                              "50 degree field of view",
                                              withoutFile(e)));
            camera.xfovDegrees = 50.0f;
            camera.aspect = 0.0f;
        }
        return chosen->world;
    }
    return std::nullopt;
}

// ===========================================================================
// Loading
// ===========================================================================

Scene ColladaLoader::load(std::vector<std::string>* warningLines) {
    const pugi::xml_node root = m_document.root();
    pugi::xml_node visualScene;
    if (const pugi::xml_node instance = root.child("scene").child("instance_visual_scene"))
        visualScene = m_document.resolve(instance.attribute("url").as_string(nullptr),
                                         "visual_scene", "<scene>");
    else
        visualScene = root.child("library_visual_scenes").child("visual_scene");
    if (!visualScene) fail("no <visual_scene>");

    const glm::dmat4 rootMatrix = rootTransform();
    for (pugi::xml_node node : visualScene.children("node")) visitNode(node, rootMatrix, 0);
    chooseInstancedGeometry();
    if (m_options.admit) m_options.admit(m_document.file(), countGeometry());
    for (const GeometryInstance& instance : m_geometryInstances) addGeometryInstance(instance);

    const uint64_t dropped = m_geometry.droppedTriangles();
    if (m_scene.meshes.empty() && m_scene.spheres.empty()) {
        if (dropped > 0) fail(fmt::format("no geometry: all {} triangles are degenerate", dropped));
        fail("no geometry: no meshes or spheres in the scene");
    }
    if (dropped > 0)
        m_warnings.addExample(
            "degenerate",
            fmt::format("dropped {} degenerate (zero-area or non-finite) triangles", dropped));
    if (m_geometry.replacedNormals() > 0)
        m_warnings.addExample("normals",
                              fmt::format("{} zero or non-finite normals replaced by face normals",
                                          m_geometry.replacedNormals()));

    for (const Mesh& mesh : m_scene.meshes)
        if (m_scene.materials[mesh.material].baseColorTexture.present() && mesh.texcoords0.empty())
            m_warnings.addCounted(
                "textured meshes without texture coordinates take one texel, at (0, 0)", "mesh",
                mesh.name);
    for (const Sphere& sphere : m_scene.spheres)
        if (m_scene.materials[sphere.material].baseColorTexture.present())
            m_warnings.addCounted("spheres have no texture coordinates: textured ones are white",
                                  "sphere", sphere.name);

    // Bounds of the file's meshes and spheres: lights (and the quads made
    // from them below) excluded, as SOURCE.md's framing rule says.
    const auto [lo, hi] = m_scene.geometryBounds();
    frameScotty3dCamera(readCamera(), lo, hi, m_scene.camera);
    const Camera& framed = m_scene.camera;
    for (const glm::vec3& v : {framed.position, framed.target})
        if (!allFinite(v))
            fail(fmt::format("the geometry's bounds {} to {} are too large to frame the camera",
                             vecString(lo), vecString(hi)));
    reconcileScotty3dLights(m_lights, (lo + hi) * 0.5f, m_scene, m_warnings);
    m_warnings.report(warningLines);
    return std::move(m_scene);
}

}  // namespace

Scene loadCollada(const std::filesystem::path& path, const LoadOptions& options,
                  std::vector<std::string>* warnings) {
    return ColladaLoader(path, options).load(warnings);
}

}  // namespace vkpath::scene
