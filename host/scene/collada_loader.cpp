// The Scotty3D COLLADA importer.
//
// Reading: <library_visual_scenes> is walked from <scene><instance_visual_scene>;
// every node's transform is the product of its <matrix> (row-major),
// <translate>, <rotate>, <scale> and <lookat> elements in document order, and
// a root transform turns Z_UP / X_UP files to +Y up exactly as Scotty3D does
// (SOURCE.md: x' = -x, y' = z, z' = y for Z_UP) and applies <unit meter>.
// Geometry is instanced per node (a geometry used twice is parsed once);
// materials are bound per instance through <bind_material> symbols.
//
// Decisions where Scotty3D is not physical or the files are ambiguous
// (each also prints a warning line when it applies):
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
// - Directional lights: colour is the irradiance in W/m^2, travelling along
//   M(0,0,-1) (the COLLADA convention; Scotty3D transforms the direction as a
//   point, translation included, which is a bug, not a choice).
// - Scotty3D's ambient light is a hemisphere (+Y) used for direct lighting
//   only, invisible to the camera; vkpath has no such light and uses a
//   constant environment of the same radiance over the whole sphere.
// - Materials follow Scotty3D: a CMU462 <mirror>, <glass>, <refraction> or
//   <emission> replaces the profile_COMMON one; otherwise the Phong/Lambert
//   <diffuse> colour is a Lambertian albedo (specular ignored), 0.5 grey
//   without one. An <emission>-only material reflects nothing (Scotty3D's
//   EmissionBSDF), so its reflectance is 0.
// - Normals: a per-corner NORMAL input is kept per vertex by splitting
//   vertices where a position has several normals. When every corner normal
//   of a primitive equals its face's normal (flat-shaded exports: the Cornell
//   boxes, the planes), the normals add nothing and are dropped so vertices
//   stay shared. Normals transform with the inverse transpose (computed as
//   the cofactor matrix, which also exists for the singular transforms some
//   of these files use); a negative determinant flips the winding.
// - Camera framing follows SOURCE.md's rule (see frameCamera).
#include "scene/collada_loader.h"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "input_error.h"

namespace vkpath::scene {
namespace {

// Caps so a broken or hostile file fails with a message instead of
// exhausting the stack (deep or cyclic node instancing) or memory.
constexpr int MAX_NODE_DEPTH = 256;
constexpr uint64_t MAX_NODE_VISITS = 1'000'000;
constexpr uint64_t MAX_TRIANGLES = 20'000'000;

constexpr uint32_t NO_NORMAL = std::numeric_limits<uint32_t>::max();

// A corner of a triangle: an index into LocalMesh::positions and one into
// LocalMesh::normals (NO_NORMAL when the primitive has none).
struct Corner {
    uint32_t position;
    uint32_t normal;
};

// One <polylist>/<triangles>/... of a <mesh>, triangulated, in file winding.
struct Primitive {
    std::string symbol;  // material symbol, bound per instance
    std::vector<Corner> corners;  // 3 per triangle
};

// A <geometry><mesh> in its own space, parsed once however often instanced.
struct LocalMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<Primitive> primitives;
    uint64_t degeneratePolygons = 0;  // fewer than 3 vertices
};

// <instance_material symbol target> pairs in document order.
using Bindings = std::vector<std::pair<std::string, std::string>>;

struct AreaLight {
    std::string name;
    glm::vec3 center, edgeX, edgeY;  // world space; edges are full side vectors
    glm::vec3 direction;             // unit, the way it emits
    glm::vec3 radiance;
};

struct PendingPointLight {
    std::string name;
    glm::vec3 position;
    glm::vec3 color;  // Scotty3D's value: no falloff
    std::optional<SpotLight> spot;  // set for spot lights (direction and cone)
};

struct CameraInstance {
    std::string nodeName;
    pugi::xml_node camera;
    glm::dmat4 world;
};

// A surface that emits, with where it is and how big, to recognise a lamp
// that the file also describes as a light.
struct Emitter {
    bool sphere;
    uint32_t index;   // into Scene::meshes or Scene::spheres
    glm::vec3 center;
    float size;       // bounding-box diagonal
    glm::vec3 normal; // area-weighted mean normal (meshes), zero for spheres
};

// Whitespace-separated tokens of an element's text.
template <class F>
void forEachToken(std::string_view text, F&& f) {
    size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
        size_t j = i;
        while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
        if (j > i) f(text.substr(i, j - i));
        i = j;
    }
}

bool parseNumber(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec == std::errc::result_out_of_range) {
        // Beyond double: an infinity the caller's finiteness checks reject.
        value = token.front() == '-' ? -HUGE_VAL : HUGE_VAL;
        return true;
    }
    return ec == std::errc() && end == token.data() + token.size();
}

bool allFinite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string vecString(const glm::vec3& v) {
    return fmt::format("({:g}, {:g}, {:g})", v.x, v.y, v.z);
}

std::string nameOf(pugi::xml_node node) {
    if (const char* name = node.attribute("name").as_string(nullptr); name && *name) return name;
    if (const char* id = node.attribute("id").as_string(nullptr); id && *id) return id;
    return fmt::format("(unnamed {})", node.name());
}

pugi::xml_node cmuTechnique(pugi::xml_node owner) {
    for (pugi::xml_node extra : owner.children("extra"))
        for (pugi::xml_node technique : extra.children("technique"))
            if (std::string_view(technique.attribute("profile").as_string()) == "CMU462")
                return technique;
    return {};
}

// Warnings are collected and printed once the file has loaded: one line per
// kind, the first occurrence's text and how many there were.
class Warnings {
  public:
    void add(const std::string& kind, std::string text) {
        for (Entry& e : m_entries)
            if (e.kind == kind) {
                ++e.count;
                return;
            }
        m_entries.push_back({kind, std::move(text), 1});
    }

    std::vector<std::string> lines() const {
        std::vector<std::string> out;
        for (const Entry& e : m_entries)
            out.push_back(e.count > 1 ? fmt::format("{} ({} like this)", e.text, e.count) : e.text);
        return out;
    }

  private:
    struct Entry {
        std::string kind;
        std::string text;
        uint64_t count;
    };
    std::vector<Entry> m_entries;
};

class ColladaLoader {
  public:
    ColladaLoader(const std::filesystem::path& path, const LoadOptions& options)
        : m_path(path), m_file(path.string()), m_options(options) {}

    Scene load(std::vector<std::string>* warningLines);

  private:
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(fmt::format("{}: {}", m_file, what));
    }

    // ---- parsing helpers -------------------------------------------------
    std::vector<double> numbers(pugi::xml_node element, const std::string& what) const;
    std::vector<uint32_t> indices(pugi::xml_node element, const std::string& what) const;
    glm::vec3 color(pugi::xml_node element, const std::string& what) const;
    double scalar(pugi::xml_node element, const std::string& what) const;
    pugi::xml_node resolve(const char* url, const char* kind, const std::string& context) const;

    // ---- document ----------------------------------------------------------
    void indexIds();
    glm::dmat4 rootTransform();
    glm::dmat4 localTransform(pugi::xml_node node);
    void visitNode(pugi::xml_node node, const glm::dmat4& parent, int depth);

    // ---- geometry ----------------------------------------------------------
    void addGeometryInstance(pugi::xml_node instance, const glm::dmat4& world,
                             const std::string& nodeName);
    const LocalMesh& localMesh(pugi::xml_node geometry);
    std::vector<glm::vec3> readVec3Source(pugi::xml_node source, bool requireFinite) const;
    void readPrimitive(pugi::xml_node element, pugi::xml_node mesh, const std::string& geometryName,
                       LocalMesh& local);
    void addMeshInstance(const LocalMesh& local, const glm::dmat4& world, const Bindings& bindings,
                         const std::string& nodeName);
    void addSphereInstance(double radius, const glm::dmat4& world, const Bindings& bindings,
                           const std::string& nodeName);

    // ---- materials ---------------------------------------------------------
    uint32_t materialFor(const std::string& symbol, const Bindings& bindings,
                         const std::string& nodeName);
    uint32_t materialIndex(const std::string& targetUrl, const std::string& context);
    Material readMaterial(pugi::xml_node material);
    uint32_t defaultMaterial();

    // ---- lights and camera -------------------------------------------------
    void addLightInstance(pugi::xml_node instance, const glm::dmat4& world,
                          const std::string& nodeName);
    std::vector<Emitter> emitters() const;
    void resolveLamps(const glm::vec3& sceneCenter);
    void addAreaLightQuad(const AreaLight& light);
    void frameCamera(const glm::vec3& boundsMin, const glm::vec3& boundsMax);

    std::filesystem::path m_path;
    std::string m_file;
    LoadOptions m_options;
    pugi::xml_document m_doc;
    std::unordered_map<std::string, pugi::xml_node> m_ids;
    std::unordered_map<const void*, LocalMesh> m_localMeshes;
    std::map<std::string, uint32_t> m_materialsById;
    std::optional<uint32_t> m_defaultMaterial;

    Scene m_scene;
    std::vector<AreaLight> m_areaLights;
    std::vector<PendingPointLight> m_pointLights;
    std::vector<CameraInstance> m_cameras;
    glm::vec3 m_ambient{0.0f};
    bool m_hasAmbient = false;

    Warnings m_warnings;
    uint64_t m_nodeVisits = 0;
    uint64_t m_triangles = 0;
    uint64_t m_droppedTriangles = 0;
    uint64_t m_replacedNormals = 0;
};

// ===========================================================================
// Parsing helpers
// ===========================================================================

std::vector<double> ColladaLoader::numbers(pugi::xml_node element, const std::string& what) const {
    std::vector<double> out;
    forEachToken(element.child_value(), [&](std::string_view token) {
        double v = 0;
        if (!parseNumber(token, v)) fail(fmt::format("{}: '{}' is not a number", what, token));
        out.push_back(v);
    });
    return out;
}

std::vector<uint32_t> ColladaLoader::indices(pugi::xml_node element,
                                             const std::string& what) const {
    std::vector<uint32_t> out;
    forEachToken(element.child_value(), [&](std::string_view token) {
        uint32_t v = 0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (ec != std::errc() || end != token.data() + token.size())
            fail(fmt::format("{}: '{}' is not an index", what, token));
        out.push_back(v);
    });
    return out;
}

glm::vec3 ColladaLoader::color(pugi::xml_node element, const std::string& what) const {
    if (!element) fail(fmt::format("{} is missing", what));
    const std::vector<double> v = numbers(element, what);
    if (v.size() < 3) fail(fmt::format("{} has {} numbers, needs 3", what, v.size()));
    const glm::vec3 c(v[0], v[1], v[2]);
    if (!allFinite(c) || c.x < 0 || c.y < 0 || c.z < 0)
        fail(fmt::format("{} {} is not a finite, non-negative colour", what, vecString(c)));
    return c;
}

double ColladaLoader::scalar(pugi::xml_node element, const std::string& what) const {
    if (!element) fail(fmt::format("{} is missing", what));
    const std::vector<double> v = numbers(element, what);
    if (v.size() != 1) fail(fmt::format("{} has {} numbers, needs 1", what, v.size()));
    if (!std::isfinite(v[0])) fail(fmt::format("{} is not finite", what));
    return v[0];
}

pugi::xml_node ColladaLoader::resolve(const char* url, const char* kind,
                                      const std::string& context) const {
    const std::string_view ref(url ? url : "");
    if (ref.empty()) fail(fmt::format("{}: no {} reference", context, kind));
    if (ref.front() != '#')
        fail(fmt::format("{}: {} reference '{}' is not in this file (external references are not "
                         "supported)",
                         context, kind, ref));
    const auto it = m_ids.find(std::string(ref.substr(1)));
    if (it == m_ids.end())
        fail(fmt::format("{}: missing referenced {} id '{}'", context, kind, ref.substr(1)));
    if (std::string_view(it->second.name()) != kind)
        fail(fmt::format("{}: '{}' is a <{}>, not a <{}>", context, ref, it->second.name(), kind));
    return it->second;
}

// ===========================================================================
// Document and node hierarchy
// ===========================================================================

void ColladaLoader::indexIds() {
    // Iterative: the XML may nest deeper than the stack allows recursion.
    std::vector<pugi::xml_node> stack{m_doc.document_element()};
    while (!stack.empty()) {
        const pugi::xml_node node = stack.back();
        stack.pop_back();
        if (const char* id = node.attribute("id").as_string(nullptr); id && *id)
            m_ids.emplace(id, node);  // the first of duplicate ids wins
        for (pugi::xml_node child : node.children())
            if (child.type() == pugi::node_element) stack.push_back(child);
    }
}

glm::dmat4 ColladaLoader::rootTransform() {
    const pugi::xml_node asset = m_doc.document_element().child("asset");
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
                m_warnings.add("unit comma", fmt::format("<unit meter=\"{}\"> has a decimal comma; read as {}", text,
                                                         pointed));
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
            std::vector<double> v = numbers(e, what);
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
            m_warnings.add("skew", fmt::format("{}: <skew> transforms are not supported and are "
                                               "ignored",
                                               nodeName));
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
    const glm::dmat4 world = parent * localTransform(node);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(world[c][r]))
                fail(fmt::format("node '{}': its world transform is not finite", nodeName));

    for (pugi::xml_node child : node.children()) {
        const std::string_view kind = child.name();
        const std::string context = fmt::format("node '{}'", nodeName);
        if (kind == "node") {
            visitNode(child, world, depth + 1);
        } else if (kind == "instance_node") {
            visitNode(resolve(child.attribute("url").as_string(nullptr), "node", context), world,
                      depth + 1);
        } else if (kind == "instance_geometry") {
            addGeometryInstance(child, world, nodeName);
        } else if (kind == "instance_camera") {
            // A camera that cannot be found is a warning, as in Scotty3D, which
            // places its camera from the scene's bounds.
            try {
                m_cameras.push_back(
                    {nodeName, resolve(child.attribute("url").as_string(nullptr), "camera", context), world});
            } catch (const InputError& e) {
                std::string reason = e.what();
                if (reason.rfind(m_file + ": ", 0) == 0) reason.erase(0, m_file.size() + 2);
                m_warnings.add("camera instance", fmt::format("{}; ignored", reason));
            }
        } else if (kind == "instance_light") {
            addLightInstance(child, world, nodeName);
        } else if (kind == "instance_controller") {
            m_warnings.add("controller",
                           fmt::format("node '{}': <instance_controller> (skinning, morphing) is "
                                       "not supported; ignored",
                                       nodeName));
        }
    }
}

// ===========================================================================
// Geometry
// ===========================================================================

std::vector<glm::vec3> ColladaLoader::readVec3Source(pugi::xml_node source,
                                                     bool requireFinite) const {
    const std::string what = fmt::format("source '{}'", nameOf(source));
    const pugi::xml_node array = source.child("float_array");
    if (!array) fail(fmt::format("{} has no <float_array>", what));
    const std::vector<double> data = numbers(array, what);
    if (const pugi::xml_attribute count = array.attribute("count")) {
        const unsigned long long declared = count.as_ullong();
        if (declared > data.size())
            fail(fmt::format("{}: <float_array> has {} numbers, its count says {}", what,
                             data.size(), declared));
    }
    uint64_t count = data.size() / 3, stride = 3, offset = 0;
    if (const pugi::xml_node accessor = source.child("technique_common").child("accessor")) {
        count = accessor.attribute("count").as_ullong();
        stride = accessor.attribute("stride").as_ullong(1);
        offset = accessor.attribute("offset").as_ullong(0);
    }
    if (stride < 3) fail(fmt::format("{}: accessor stride {} is below 3 (x y z)", what, stride));
    // Checked before multiplying so absurd counts cannot overflow.
    if (count > data.size() || stride > data.size() || offset > data.size() ||
        (count > 0 && offset + (count - 1) * stride + 3 > data.size()))
        fail(fmt::format("{}: accessor (count {}, stride {}, offset {}) reads past its {} numbers",
                         what, count, stride, offset, data.size()));
    std::vector<glm::vec3> out(count);
    for (uint64_t i = 0; i < count; ++i) {
        const double* v = &data[offset + i * stride];
        out[i] = glm::vec3(v[0], v[1], v[2]);
        if (requireFinite && !allFinite(out[i]))
            fail(fmt::format("{}: element {} {} is not finite", what, i, vecString(out[i])));
    }
    return out;
}

// One primitive element of a <mesh>: its inputs, index stride and polygons,
// triangulated as fans (polylist, polygons, trifans) or strips (tristrips).
void ColladaLoader::readPrimitive(pugi::xml_node element, pugi::xml_node mesh,
                                  const std::string& geometryName, LocalMesh& local) {
    const std::string_view kind = element.name();
    const std::string what = fmt::format("geometry '{}': <{}>", geometryName, kind);
    Primitive primitive;
    primitive.symbol = element.attribute("material").as_string();

    uint64_t stride = 1;
    std::optional<uint64_t> vertexOffset, normalOffset;
    bool normalsPerPosition = false;
    std::vector<glm::vec3> normals;
    for (pugi::xml_node input : element.children("input")) {
        const std::string_view semantic = input.attribute("semantic").as_string();
        const uint64_t offset = input.attribute("offset").as_ullong(0);
        if (offset > 1'000'000) fail(fmt::format("{}: input offset {} is absurd", what, offset));
        stride = std::max(stride, offset + 1);
        const char* sourceUrl = input.attribute("source").as_string(nullptr);
        if (semantic == "VERTEX") {
            const pugi::xml_node vertices = resolve(sourceUrl, "vertices", what);
            if (vertices.parent() != mesh)
                fail(fmt::format("{}: VERTEX refers to the <vertices> of another mesh", what));
            vertexOffset = offset;
            bool havePositions = false;
            for (pugi::xml_node vin : vertices.children("input")) {
                const std::string_view vsemantic = vin.attribute("semantic").as_string();
                const char* url = vin.attribute("source").as_string(nullptr);
                if (vsemantic == "POSITION") {
                    local.positions = readVec3Source(resolve(url, "source", what), true);
                    havePositions = true;
                } else if (vsemantic == "NORMAL") {
                    normals = readVec3Source(resolve(url, "source", what), false);
                    normalsPerPosition = true;
                }
            }
            if (!havePositions) fail(fmt::format("{}: its <vertices> has no POSITION input", what));
        } else if (semantic == "NORMAL") {
            normals = readVec3Source(resolve(sourceUrl, "source", what), false);
            normalOffset = offset;
            normalsPerPosition = false;
        }
        // TEXCOORD, COLOR, ...: nothing in the scene model uses them.
    }
    if (!vertexOffset) fail(fmt::format("{} has no VERTEX input", what));
    if (normalsPerPosition && normals.size() < local.positions.size())
        fail(fmt::format("{}: {} per-vertex normals for {} positions", what, normals.size(),
                         local.positions.size()));

    // Every primitive of a mesh shares the <vertices>; normals are per
    // primitive, so they are appended and indices rebased.
    const uint32_t normalBase = static_cast<uint32_t>(local.normals.size());
    local.normals.insert(local.normals.end(), normals.begin(), normals.end());

    auto corner = [&](const std::vector<uint32_t>& p, uint64_t k) {
        const uint32_t position = p[k * stride + *vertexOffset];
        if (position >= local.positions.size())
            fail(fmt::format("{}: position index {} out of range of its source ({} elements)",
                             what, position, local.positions.size()));
        uint32_t normal = NO_NORMAL;
        if (normalOffset) {
            normal = p[k * stride + *normalOffset];
            if (normal >= normals.size())
                fail(fmt::format("{}: normal index {} out of range of its source ({} elements)",
                                 what, normal, normals.size()));
            normal += normalBase;
        } else if (normalsPerPosition) {
            normal = position + normalBase;
        }
        return Corner{position, normal};
    };
    auto addFan = [&](const std::vector<uint32_t>& p, uint64_t first, uint64_t n) {
        if (n < 3) {
            ++local.degeneratePolygons;
            return;
        }
        for (uint64_t i = 1; i + 1 < n; ++i)
            for (uint64_t k : {first, first + i, first + i + 1})
                primitive.corners.push_back(corner(p, k));
    };
    auto addStrip = [&](const std::vector<uint32_t>& p, uint64_t n) {
        if (n < 3) {
            ++local.degeneratePolygons;
            return;
        }
        for (uint64_t i = 0; i + 2 < n; ++i) {
            // Every other triangle of a strip is listed clockwise.
            const bool odd = i % 2 == 1;
            for (uint64_t k : {i, odd ? i + 2 : i + 1, odd ? i + 1 : i + 2})
                primitive.corners.push_back(corner(p, k));
        }
    };
    auto checkedIndices = [&](pugi::xml_node p, uint64_t cornersNeeded) {
        std::vector<uint32_t> values = indices(p, what + " <p>");
        if (cornersNeeded > values.size() / stride)
            fail(fmt::format("{}: <p> has {} indices, needs {} ({} corners of {} inputs)", what,
                             values.size(), cornersNeeded * stride, cornersNeeded, stride));
        return values;
    };

    const pugi::xml_attribute countAttribute = element.attribute("count");
    uint64_t count = countAttribute.as_ullong(0);
    if (kind == "polylist") {
        const std::vector<uint32_t> vcount = indices(element.child("vcount"), what + " <vcount>");
        if (!countAttribute) count = vcount.size();
        if (count > vcount.size())
            fail(fmt::format("{}: <vcount> has {} entries, count says {}", what, vcount.size(),
                             count));
        uint64_t total = 0;
        for (uint64_t i = 0; i < count; ++i) total += vcount[i];  // each < 2^32: no overflow
        const std::vector<uint32_t> p = checkedIndices(element.child("p"), total);
        uint64_t first = 0;
        for (uint64_t i = 0; i < count; ++i) {
            addFan(p, first, vcount[i]);
            first += vcount[i];
        }
    } else if (kind == "triangles") {
        if (!countAttribute) count = indices(element.child("p"), what + " <p>").size() / stride / 3;
        const std::vector<uint32_t> p = checkedIndices(element.child("p"), count * 3);
        for (uint64_t t = 0; t < count; ++t) addFan(p, t * 3, 3);
    } else {
        // <polygons>, <trifans>, <tristrips>: one <p> per polygon, fan or strip.
        uint64_t seen = 0;
        for (pugi::xml_node pNode : element.children("p")) {
            const std::vector<uint32_t> p = checkedIndices(pNode, 0);
            const uint64_t n = p.size() / stride;
            if (kind == "tristrips")
                addStrip(p, n);
            else
                addFan(p, 0, n);
            ++seen;
        }
        if (element.child("ph"))
            m_warnings.add("holes", fmt::format("{}: polygons with holes (<ph>) are not "
                                                "supported; ignored",
                                                what));
        if (seen < count)
            fail(fmt::format("{}: has {} <p> elements, count says {}", what, seen, count));
    }
    local.primitives.push_back(std::move(primitive));
}

const LocalMesh& ColladaLoader::localMesh(pugi::xml_node geometry) {
    const auto cached = m_localMeshes.find(geometry.internal_object());
    if (cached != m_localMeshes.end()) return cached->second;
    const std::string geometryName = nameOf(geometry);
    const pugi::xml_node mesh = geometry.child("mesh");
    LocalMesh local;
    for (pugi::xml_node element : mesh.children()) {
        const std::string_view kind = element.name();
        if (kind == "polylist" || kind == "triangles" || kind == "polygons" || kind == "trifans" ||
            kind == "tristrips") {
            readPrimitive(element, mesh, geometryName, local);
        } else if (kind == "lines" || kind == "linestrips") {
            m_warnings.add("lines", fmt::format("geometry '{}': <{}> has no area; ignored",
                                                geometryName, kind));
        }
    }
    return m_localMeshes.emplace(geometry.internal_object(), std::move(local)).first->second;
}

void ColladaLoader::addGeometryInstance(pugi::xml_node instance, const glm::dmat4& world,
                                        const std::string& nodeName) {
    const std::string context = fmt::format("node '{}'", nodeName);
    const pugi::xml_node geometry =
        resolve(instance.attribute("url").as_string(nullptr), "geometry", context);
    Bindings bindings;
    for (pugi::xml_node im :
         instance.child("bind_material").child("technique_common").children("instance_material"))
        bindings.emplace_back(im.attribute("symbol").as_string(),
                              im.attribute("target").as_string());

    // Scotty3D's order: a <mesh> makes a mesh, else the CMU462 <sphere>.
    if (geometry.child("mesh")) {
        addMeshInstance(localMesh(geometry), world, bindings, nodeName);
        return;
    }
    if (const pugi::xml_node sphere = cmuTechnique(geometry).child("sphere")) {
        const std::string what = fmt::format("geometry '{}': sphere", nameOf(geometry));
        const double radius = scalar(sphere.child("radius"), what + " <radius>");
        if (!(radius > 0)) fail(fmt::format("{} radius {} is not positive", what, radius));
        addSphereInstance(radius, world, bindings, nodeName);
        return;
    }
    m_warnings.add("geometry-kind",
                   fmt::format("geometry '{}' has neither a <mesh> nor a CMU462 <sphere> (splines, "
                               "convex meshes are not supported); ignored",
                               nameOf(geometry)));
}

void ColladaLoader::addMeshInstance(const LocalMesh& local, const glm::dmat4& world,
                                    const Bindings& bindings, const std::string& nodeName) {
    m_droppedTriangles += local.degeneratePolygons;
    const glm::dmat3 linear(world);
    const double det = glm::determinant(linear);
    // Cofactor matrix = det * inverse transpose: transforms normals (and maps
    // a x b to (La) x (Lb)) even when the transform is singular.
    const glm::dmat3 cofactor(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                              glm::cross(linear[0], linear[1]));
    const bool flip = det < 0;

    std::vector<glm::vec3> positions(local.positions.size());
    for (size_t i = 0; i < positions.size(); ++i)
        positions[i] = glm::vec3(world * glm::dvec4(glm::dvec3(local.positions[i]), 1.0));
    std::vector<glm::vec3> normals(local.normals.size());
    std::vector<uint8_t> normalValid(local.normals.size(), 0);
    for (size_t i = 0; i < normals.size(); ++i) {
        glm::dvec3 n = cofactor * glm::dvec3(local.normals[i]);
        if (flip) n = -n;
        const double len = glm::length(n);
        if (len > 0 && std::isfinite(len)) {
            normals[i] = glm::vec3(n / len);
            normalValid[i] = allFinite(normals[i]);
        }
    }

    for (size_t k = 0; k < local.primitives.size(); ++k) {
        const Primitive& primitive = local.primitives[k];
        const size_t triangleCount = primitive.corners.size() / 3;

        // Pass 1: which triangles survive, their face normals, and whether
        // the corner normals say anything the faces do not.
        std::vector<glm::vec3> faceNormals(triangleCount);
        std::vector<uint8_t> keep(triangleCount, 0);
        bool anyNormals = false, flat = true;
        auto cornerOf = [&](size_t t, int i) {
            // A mirroring transform turns counter-clockwise into clockwise.
            const int j = flip && i > 0 ? 3 - i : i;
            return primitive.corners[t * 3 + j];
        };
        for (size_t t = 0; t < triangleCount; ++t) {
            const glm::vec3 p0 = positions[cornerOf(t, 0).position];
            const glm::vec3 p1 = positions[cornerOf(t, 1).position];
            const glm::vec3 p2 = positions[cornerOf(t, 2).position];
            const glm::vec3 e1 = p1 - p0, e2 = p2 - p0, e3 = p2 - p1;
            const glm::vec3 cross = glm::cross(e1, e2);
            const float twiceArea = glm::length(cross);
            const float longest = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
            // Relative test: the sine of the smallest angle below float
            // precision means no well-defined plane.
            if (!allFinite(p0) || !allFinite(p1) || !allFinite(p2) || !std::isfinite(twiceArea) ||
                !(twiceArea > 1e-7f * longest)) {
                ++m_droppedTriangles;
                continue;
            }
            keep[t] = 1;
            faceNormals[t] = cross / twiceArea;
            for (int i = 0; i < 3; ++i) {
                const uint32_t n = cornerOf(t, i).normal;
                if (n == NO_NORMAL) continue;
                anyNormals = true;
                if (!normalValid[n]) {
                    ++m_replacedNormals;
                    continue;
                }
                flat = flat && glm::dot(normals[n], faceNormals[t]) > 1.0f - 1e-4f;
            }
        }
        const bool keepNormals = anyNormals && !flat;

        // Pass 2: vertices shared per (position, normal) pair.
        Mesh mesh;
        mesh.name = local.primitives.size() > 1 ? fmt::format("{}#{}", nodeName, k) : nodeName;
        mesh.material = materialFor(primitive.symbol, bindings, nodeName);
        std::unordered_map<uint64_t, uint32_t> vertexOf;
        auto vertex = [&](const Corner& c, const glm::vec3& faceNormal) -> uint32_t {
            const bool ownNormal = keepNormals && c.normal != NO_NORMAL && normalValid[c.normal];
            if (keepNormals && !ownNormal) {
                // An invalid normal: this corner takes its face's, unshared.
                mesh.positions.push_back(positions[c.position]);
                mesh.normals.push_back(faceNormal);
                return static_cast<uint32_t>(mesh.positions.size() - 1);
            }
            const uint64_t key =
                (uint64_t(c.position) << 32) | (ownNormal ? c.normal : uint64_t(0xffffffffu));
            const auto [it, inserted] =
                vertexOf.emplace(key, static_cast<uint32_t>(mesh.positions.size()));
            if (inserted) {
                mesh.positions.push_back(positions[c.position]);
                if (keepNormals) mesh.normals.push_back(normals[c.normal]);
            }
            return it->second;
        };
        for (size_t t = 0; t < triangleCount; ++t) {
            if (!keep[t]) continue;
            glm::uvec3 tri;
            for (int i = 0; i < 3; ++i) tri[i] = vertex(cornerOf(t, i), faceNormals[t]);
            mesh.triangles.push_back(tri);
        }
        if (mesh.triangles.empty()) continue;
        m_triangles += mesh.triangles.size();
        if (m_triangles > MAX_TRIANGLES)
            fail(fmt::format("more than {} triangles after instancing", MAX_TRIANGLES));
        m_scene.meshes.push_back(std::move(mesh));
    }
}

void ColladaLoader::addSphereInstance(double radius, const glm::dmat4& world,
                                      const Bindings& bindings, const std::string& nodeName) {
    const glm::dmat3 linear(world);
    const double s0 = glm::length(linear[0]), s1 = glm::length(linear[1]),
                 s2 = glm::length(linear[2]);
    const double largest = std::max({s0, s1, s2}), smallest = std::min({s0, s1, s2});
    const glm::vec3 center(world * glm::dvec4(0, 0, 0, 1));
    if (!(largest > 0) || !allFinite(center)) {
        m_warnings.add("sphere-degenerate",
                       fmt::format("node '{}': sphere with a zero-scale transform dropped",
                                   nodeName));
        return;
    }
    // Uniform scale: equal, mutually orthogonal columns.
    const double tolerance = 1e-4 * largest * largest;
    const bool orthogonal = std::abs(glm::dot(linear[0], linear[1])) < tolerance &&
                            std::abs(glm::dot(linear[1], linear[2])) < tolerance &&
                            std::abs(glm::dot(linear[0], linear[2])) < tolerance;
    double scale = largest;
    if (!orthogonal || largest - smallest > 1e-4 * largest) {
        scale = (s0 + s1 + s2) / 3.0;
        m_warnings.add("sphere-scale",
                       fmt::format("node '{}': non-uniform scale ({:g}, {:g}, {:g}) on a sphere; "
                                   "approximated by a sphere of the mean scale {:g}",
                                   nodeName, s0, s1, s2, scale));
    }
    Sphere sphere;
    sphere.name = nodeName;
    sphere.center = center;
    sphere.radius = static_cast<float>(radius * scale);
    if (!(sphere.radius > 0) || !std::isfinite(sphere.radius))
        fail(fmt::format("node '{}': sphere radius {} is not a positive float", nodeName,
                         radius * scale));
    // A sphere has no primitive symbol; Scotty3D takes the first binding.
    sphere.material = materialFor("", bindings, nodeName);
    m_scene.spheres.push_back(sphere);
}

// ===========================================================================
// Materials
// ===========================================================================

uint32_t ColladaLoader::defaultMaterial() {
    if (!m_defaultMaterial) {
        Material m;
        m.name = "default";
        m.reflectance = glm::vec3(0.5f);  // Scotty3D's DiffuseBSDF for unbound meshes
        m_defaultMaterial = static_cast<uint32_t>(m_scene.materials.size());
        m_scene.materials.push_back(m);
    }
    return *m_defaultMaterial;
}

uint32_t ColladaLoader::materialFor(const std::string& symbol, const Bindings& bindings,
                                    const std::string& nodeName) {
    const std::string context = fmt::format("node '{}'", nodeName);
    if (!symbol.empty())
        for (const auto& [s, target] : bindings)
            if (s == symbol) return materialIndex(target, context);
    if (!symbol.empty())
        m_warnings.add("unbound-symbol",
                       fmt::format("{}: material symbol '{}' is not bound; using {} (as Scotty3D)",
                                   context, symbol,
                                   bindings.empty() ? "grey 0.5"
                                                    : "the instance's first material"));
    if (!bindings.empty()) return materialIndex(bindings.front().second, context);
    return defaultMaterial();
}

uint32_t ColladaLoader::materialIndex(const std::string& targetUrl, const std::string& context) {
    const pugi::xml_node material = resolve(targetUrl.c_str(), "material", context);
    const std::string id = material.attribute("id").as_string();
    if (const auto it = m_materialsById.find(id); it != m_materialsById.end()) return it->second;
    const uint32_t index = static_cast<uint32_t>(m_scene.materials.size());
    Material m = readMaterial(material);
    m_scene.materials.push_back(std::move(m));
    m_materialsById.emplace(id, index);
    return index;
}

Material ColladaLoader::readMaterial(pugi::xml_node material) {
    Material m;
    m.name = nameOf(material);
    const std::string what = fmt::format("material '{}'", m.name);
    const pugi::xml_node effect =
        resolve(material.child("instance_effect").attribute("url").as_string(nullptr), "effect",
                what);

    const pugi::xml_node cmu = cmuTechnique(effect);
    bool haveBsdf = false, haveEmission = false;
    for (pugi::xml_node bsdf : cmu.children()) {
        const std::string_view kind = bsdf.name();
        const std::string where = fmt::format("{}: CMU462 <{}>", what, kind);
        auto optionalColor = [&](const char* child, glm::vec3 fallback) {
            const pugi::xml_node e = bsdf.child(child);
            return e ? color(e, fmt::format("{} <{}>", where, child)) : fallback;
        };
        if (kind == "emission") {
            m.emission = color(bsdf.child("radiance"), where + " <radiance>");
            haveEmission = true;
        } else if (kind == "mirror") {
            m.kind = MaterialKind::Mirror;
            m.reflectance = optionalColor("reflectance", glm::vec3(1.0f));
            haveBsdf = true;
        } else if (kind == "glass" || kind == "refraction") {
            m.kind = MaterialKind::Dielectric;
            m.transmittance = optionalColor("transmittance", glm::vec3(1.0f));
            // Scotty3D's RefractionBSDF only transmits: no reflected tint.
            m.reflectance = kind == "glass" ? optionalColor("reflectance", glm::vec3(1.0f))
                                            : glm::vec3(0.0f);
            if (kind == "refraction")
                m_warnings.add("refraction",
                               fmt::format("{}: refraction-only BSDF approximated by glass "
                                           "with zero reflectance",
                                           what));
            if (const pugi::xml_node ior = bsdf.child("ior")) {
                const double value = scalar(ior, where + " <ior>");
                if (!(value > 0)) fail(fmt::format("{} <ior> {} is not positive", where, value));
                m.ior = static_cast<float>(value);
            } else {
                m_warnings.add("ior", fmt::format("{} has no <ior>; using 1.5", where));
            }
            if (const pugi::xml_node roughness = bsdf.child("roughness");
                roughness && scalar(roughness, where + " <roughness>") != 0.0)
                m_warnings.add("roughness",
                               fmt::format("{}: rough glass is rendered smooth", what));
            haveBsdf = true;
        } else {
            m_warnings.add("cmu-bsdf",
                           fmt::format("{}: unknown CMU462 BSDF <{}> ignored", what, kind));
        }
    }
    if (haveEmission && !haveBsdf) {
        // Scotty3D's EmissionBSDF emits and reflects nothing.
        m.reflectance = glm::vec3(0.0f);
        return m;
    }
    if (haveEmission)
        m_warnings.add("emission-bsdf",
                       fmt::format("{}: CMU462 <emission> together with a BSDF; vkpath keeps both "
                                   "(Scotty3D keeps the last)",
                                   what));
    if (haveBsdf) return m;

    // profile_COMMON: the shading model's <diffuse> colour is a Lambertian albedo.
    pugi::xml_node shading;
    for (pugi::xml_node technique : effect.child("profile_COMMON").children("technique"))
        for (const char* model : {"phong", "blinn", "lambert", "constant"})
            if (!shading) shading = technique.child(model);
    m.kind = MaterialKind::Diffuse;
    m.reflectance = glm::vec3(0.5f);
    if (const pugi::xml_node diffuse = shading.child("diffuse")) {
        if (diffuse.child("color")) {
            m.reflectance = color(diffuse.child("color"), what + " <diffuse><color>");
        } else if (diffuse.child("texture")) {
            m_warnings.add("texture", fmt::format("{}: textures are not supported; using grey 0.5",
                                                  what));
        }
    }
    if (glm::any(glm::greaterThan(m.reflectance, glm::vec3(1.0f)))) {
        m_warnings.add("albedo", fmt::format("{}: diffuse albedo {} above 1 clamped", what,
                                             vecString(m.reflectance)));
        m.reflectance = glm::min(m.reflectance, glm::vec3(1.0f));
    }
    if (const pugi::xml_node specular = shading.child("specular").child("color")) {
        const glm::vec3 s = color(specular, what + " <specular><color>");
        if (s != glm::vec3(0.0f))
            m_warnings.add("specular",
                           fmt::format("{}: Phong/Blinn specular {} is not modelled; the surface "
                                       "is Lambertian in its diffuse colour (as in Scotty3D)",
                                       what, vecString(s)));
    }
    if (const pugi::xml_node emission = shading.child("emission").child("color")) {
        const glm::vec3 e = color(emission, what + " <emission><color>");
        if (e != glm::vec3(0.0f))
            m_warnings.add("common-emission",
                           fmt::format("{}: profile_COMMON emission {} ignored (Scotty3D emits "
                                       "only through CMU462 <emission><radiance>)",
                                       what, vecString(e)));
    }
    if (shading.child("transparent") || shading.child("transparency"))
        m_warnings.add("transparency",
                       fmt::format("{}: transparency is not modelled; the surface is opaque",
                                   what));
    return m;
}

// ===========================================================================
// Lights
// ===========================================================================

void ColladaLoader::addLightInstance(pugi::xml_node instance, const glm::dmat4& world,
                                     const std::string& nodeName) {
    const pugi::xml_node light = resolve(instance.attribute("url").as_string(nullptr), "light",
                                         fmt::format("node '{}'", nodeName));
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
        m_warnings.add("light-empty", fmt::format("{} has no light type; ignored", what));
        return;
    }
    const std::string_view kind = type.name();
    const glm::dmat3 linear(world);
    const glm::vec3 position(world * glm::dvec4(0, 0, 0, 1));
    const glm::vec3 forward(linear * glm::dvec3(0, 0, -1));  // COLLADA lights point down -Z
    auto lightColor = [&] { return color(type.child("color"), fmt::format("{} <color>", what)); };

    if (kind == "area") {
        AreaLight area{name,
                       position,
                       glm::vec3(linear * glm::dvec3(-1, 0, 0)),
                       glm::vec3(linear * glm::dvec3(0, 1, 0)),
                       forward,
                       lightColor()};
        const float length = glm::length(forward);
        if (!(glm::length(glm::cross(area.edgeX, area.edgeY)) > 0) || !(length > 0) ||
            !allFinite(area.center)) {
            m_warnings.add("light-degenerate",
                           fmt::format("{}: zero-size area light dropped", what));
            return;
        }
        area.direction = forward / length;
        m_areaLights.push_back(area);
    } else if (kind == "point" || kind == "spot") {
        PendingPointLight point{name, position, lightColor(), std::nullopt};
        if (kind == "spot") {
            const float length = glm::length(forward);
            if (!(length > 0)) {
                m_warnings.add("light-degenerate",
                               fmt::format("{}: spot light without a direction dropped", what));
                return;
            }
            SpotLight spot;
            spot.direction = forward / length;
            // falloff_angle is the cone's full angle (Blender's spot size);
            // falloff_exponent (Blender's blend) sets the soft edge.
            double falloff = 180.0, blend = 0.15;
            if (type.child("falloff_angle"))
                falloff = scalar(type.child("falloff_angle"), what + " <falloff_angle>");
            if (type.child("falloff_exponent"))
                blend = scalar(type.child("falloff_exponent"), what + " <falloff_exponent>");
            if (!(falloff > 0 && falloff <= 360))
                fail(fmt::format("{}: falloff_angle {} is not in (0, 360]", what, falloff));
            spot.outerConeAngle = static_cast<float>(glm::radians(std::min(falloff, 180.0)) / 2);
            spot.innerConeAngle =
                static_cast<float>(spot.outerConeAngle * (1.0 - std::clamp(blend, 0.0, 1.0)));
            point.spot = spot;
            m_warnings.add("spot", fmt::format("{}: spot light approximated (Scotty3D does not "
                                               "render spot lights; cone from falloff_angle)",
                                               what));
        }
        m_pointLights.push_back(point);
    } else if (kind == "directional") {
        const float length = glm::length(forward);
        if (!(length > 0)) {
            m_warnings.add("light-degenerate",
                           fmt::format("{}: directional light without a direction dropped", what));
            return;
        }
        m_scene.directionalLights.push_back({forward / length, lightColor()});
    } else if (kind == "ambient") {
        m_ambient += lightColor();
        m_hasAmbient = true;
        m_warnings.add("ambient",
                       fmt::format("{}: Scotty3D's ambient light is a +Y hemisphere for direct "
                                   "lighting only, invisible to the camera; vkpath uses a constant "
                                   "environment of the same radiance over the whole sphere",
                                   what));
    } else {
        m_warnings.add("light-type",
                       fmt::format("{}: light type <{}> is not supported; ignored", what, kind));
    }
}

std::vector<Emitter> ColladaLoader::emitters() const {
    std::vector<Emitter> out;
    for (uint32_t i = 0; i < m_scene.meshes.size(); ++i) {
        const Mesh& mesh = m_scene.meshes[i];
        if (!m_scene.materials[mesh.material].emissive()) continue;
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
    for (uint32_t i = 0; i < m_scene.spheres.size(); ++i) {
        const Sphere& s = m_scene.spheres[i];
        if (m_scene.materials[s.material].emissive())
            out.push_back({true, i, s.center, 2.0f * std::sqrt(3.0f) * s.radius, glm::vec3(0.0f)});
    }
    return out;
}

void ColladaLoader::addAreaLightQuad(const AreaLight& light) {
    Material material;
    material.name = fmt::format("area light '{}'", light.name);
    material.reflectance = glm::vec3(0.0f);  // a light, not a reflector
    material.emission = light.radiance;
    Mesh mesh;
    mesh.name = material.name;
    mesh.material = static_cast<uint32_t>(m_scene.materials.size());
    m_scene.materials.push_back(material);
    const glm::vec3 hx = 0.5f * light.edgeX, hy = 0.5f * light.edgeY;
    mesh.positions = {light.center - hx - hy, light.center + hx - hy, light.center + hx + hy,
                      light.center - hx + hy};
    // Counter-clockwise seen from the side it lights, so the front faces it.
    if (glm::dot(glm::cross(light.edgeX, light.edgeY), light.direction) >= 0)
        mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    else
        mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
    m_scene.meshes.push_back(std::move(mesh));
}

void ColladaLoader::resolveLamps(const glm::vec3& sceneCenter) {
    // ---- area lights: the lamp mesh if there is one, else a quad -----------
    for (const AreaLight& light : m_areaLights) {
        const float tolerance = 0.1f * glm::length(light.edgeX + light.edgeY);
        const Emitter* match = nullptr;
        float best = tolerance;
        const std::vector<Emitter> all = emitters();
        for (const Emitter& e : all) {
            const float distance = glm::length(e.center - light.center);
            if (distance <= best) {
                best = distance;
                match = &e;
            }
        }
        if (!match) {
            m_warnings.add("area-quad",
                           fmt::format("area light '{}' has no emissive mesh at its centre; "
                                       "rendered as an emissive {:g} x {:g} m quad facing {}",
                                       light.name, glm::length(light.edgeX),
                                       glm::length(light.edgeY), vecString(light.direction)));
            addAreaLightQuad(light);
            continue;
        }
        const std::string emitterName = match->sphere ? m_scene.spheres[match->index].name
                                                      : m_scene.meshes[match->index].name;
        m_warnings.add("area-merged",
                       fmt::format("area light '{}' and emissive {} '{}' ({:.3g} m apart) "
                                   "describe one lamp; the {} emits, the area light is dropped",
                                   light.name, match->sphere ? "sphere" : "mesh", emitterName, best,
                                   match->sphere ? "sphere" : "mesh"));
        uint32_t& materialIndexRef = match->sphere ? m_scene.spheres[match->index].material
                                                   : m_scene.meshes[match->index].material;
        const glm::vec3 meshRadiance = m_scene.materials[materialIndexRef].emission;
        const glm::vec3 difference = glm::abs(meshRadiance - light.radiance);
        const glm::vec3 scale = glm::max(meshRadiance, light.radiance);
        if (glm::any(glm::greaterThan(difference, 1e-3f * scale))) {
            // See the file comment: the area light's value lit Scotty3D's images.
            m_warnings.add("area-radiance",
                           fmt::format("area light '{}' radiance {} and lamp '{}' radiance {} "
                                       "disagree; using the area light's",
                                       light.name, vecString(light.radiance), emitterName,
                                       vecString(meshRadiance)));
            Material copy = m_scene.materials[materialIndexRef];
            copy.name += " (area light radiance)";
            copy.emission = light.radiance;
            materialIndexRef = static_cast<uint32_t>(m_scene.materials.size());
            m_scene.materials.push_back(copy);
        }
        if (!match->sphere && glm::dot(match->normal, light.direction) < 0) {
            Mesh& mesh = m_scene.meshes[match->index];
            for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
            for (glm::vec3& n : mesh.normals) n = -n;
            m_warnings.add("lamp-flipped",
                           fmt::format("lamp mesh '{}' faced away from area light '{}'; turned to "
                                       "face {}",
                                       mesh.name, light.name, vecString(light.direction)));
        }
    }

    // ---- point and spot lights ---------------------------------------------
    const std::vector<Emitter> all = emitters();
    for (const PendingPointLight& light : m_pointLights) {
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
            m_warnings.add("point-merged",
                           fmt::format("point light '{}' is {:.3g} m from the centre of emissive "
                                       "{} '{}': the same lamp; dropped, the {} emits",
                                       light.name, best, match->sphere ? "sphere" : "mesh",
                                       match->sphere ? m_scene.spheres[match->index].name
                                                     : m_scene.meshes[match->index].name,
                                       match->sphere ? "sphere" : "mesh"));
            continue;
        }
        // Scotty3D: irradiance colour x cos at any distance. Physical: I / d^2.
        const float d = glm::length(sceneCenter - light.position);
        const float d2 = d > 1e-6f ? d * d : 1.0f;
        const glm::vec3 intensity = light.color * d2;
        m_warnings.add(light.spot ? "spot-falloff" : "point-falloff",
                       fmt::format("{} light '{}': Scotty3D's has no falloff; converted to an "
                                   "inverse-square light of intensity {} W/sr (colour x d^2, d = "
                                   "{:.3g} m to the scene centre, where the irradiance matches)",
                                   light.spot ? "spot" : "point", light.name, vecString(intensity),
                                   d));
        if (light.spot) {
            SpotLight spot = *light.spot;
            spot.position = light.position;
            spot.intensity = intensity;
            m_scene.spotLights.push_back(spot);
        } else {
            m_scene.pointLights.push_back({light.position, intensity});
        }
    }

    if (m_hasAmbient) {
        Environment environment;
        environment.color = m_ambient;
        m_scene.environment = environment;
    }
}

// ===========================================================================
// Camera
// ===========================================================================

// SOURCE.md, "How Scotty3D frames these scenes": keep only the direction of
// the COLLADA camera and re-aim it at the scene.
void ColladaLoader::frameCamera(const glm::vec3& boundsMin, const glm::vec3& boundsMax) {
    Camera& camera = m_scene.camera;
    glm::dvec3 d(0, 0, 1);  // no camera: look down -Z from +Z
    if (m_cameras.empty()) {
        m_warnings.add("no-camera", "no camera; framing the scene from +Z with a 50 degree fov");
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
                fail(fmt::format("no camera named '{}' (cameras: {})", m_options.cameraName,
                                 names));
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
                m_warnings.add("orthographic",
                               what + ": orthographic camera approximated by a 50 degree perspective");
                camera.xfovDegrees = 50.0f;
            } else {
                double aspect = 0;
                if (perspective.child("aspect_ratio")) {
                    aspect = scalar(perspective.child("aspect_ratio"), what + " <aspect_ratio>");
                    if (!(aspect > 0))
                        fail(fmt::format("{}: aspect_ratio {} is not positive", what, aspect));
                }
                double xfov = 0;
                if (perspective.child("xfov")) {
                    xfov = scalar(perspective.child("xfov"), what + " <xfov>");
                } else if (perspective.child("yfov")) {
                    const double yfov = scalar(perspective.child("yfov"), what + " <yfov>");
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
            std::string reason = e.what();
            if (reason.rfind(m_file + ": ", 0) == 0) reason.erase(0, m_file.size() + 2);
            m_warnings.add("camera optics", fmt::format("{}; the camera keeps its direction with Scotty3D's 50 degree "
                                                        "field of view",
                                                        reason));
            camera.xfovDegrees = 50.0f;
            camera.aspect = 0.0f;
        }
        // Step 2: the view direction transformed as a point, translation
        // included (M already holds step 1's Z_UP turn).
        const glm::dvec3 point(chosen->world * glm::dvec4(0, 0, -1, 1));
        const glm::dvec3 back = -(glm::dmat3(chosen->world) * glm::dvec3(0, 0, -1));
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

// ===========================================================================
// Loading
// ===========================================================================

Scene ColladaLoader::load(std::vector<std::string>* warningLines) {
    const pugi::xml_parse_result parsed = m_doc.load_file(m_path.c_str());
    if (parsed.status == pugi::status_file_not_found) fail("no such file");
    if (parsed.status == pugi::status_io_error || parsed.status == pugi::status_out_of_memory)
        fail(fmt::format("cannot read: {}", parsed.description()));
    if (!parsed)
        fail(fmt::format("malformed XML at byte {}: {}", parsed.offset, parsed.description()));
    const pugi::xml_node root = m_doc.document_element();
    if (std::string_view(root.name()) != "COLLADA")
        fail(fmt::format("not a COLLADA document (the root element is <{}>)", root.name()));
    indexIds();

    pugi::xml_node visualScene;
    if (const pugi::xml_node instance = root.child("scene").child("instance_visual_scene"))
        visualScene = resolve(instance.attribute("url").as_string(nullptr), "visual_scene",
                              "<scene>");
    else
        visualScene = root.child("library_visual_scenes").child("visual_scene");
    if (!visualScene) fail("no <visual_scene>");

    const glm::dmat4 rootMatrix = rootTransform();
    for (pugi::xml_node node : visualScene.children("node")) visitNode(node, rootMatrix, 0);

    if (m_scene.meshes.empty() && m_scene.spheres.empty()) {
        if (m_droppedTriangles > 0)
            fail(fmt::format("no geometry: all {} triangles are degenerate", m_droppedTriangles));
        fail("no geometry: no meshes or spheres in the scene");
    }
    if (m_droppedTriangles > 0)
        m_warnings.add("degenerate", fmt::format("dropped {} degenerate (zero-area or non-finite) "
                                                 "triangles",
                                                 m_droppedTriangles));
    if (m_replacedNormals > 0)
        m_warnings.add("normals", fmt::format("{} zero or non-finite normals replaced by face "
                                              "normals",
                                              m_replacedNormals));

    // Bounds of the file's meshes and spheres: lights (and the quads made
    // from them below) excluded, as SOURCE.md's framing rule says.
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Mesh& mesh : m_scene.meshes)
        for (const glm::uvec3& t : mesh.triangles)
            for (int i = 0; i < 3; ++i) {
                lo = glm::min(lo, mesh.positions[t[i]]);
                hi = glm::max(hi, mesh.positions[t[i]]);
            }
    for (const Sphere& s : m_scene.spheres) {
        lo = glm::min(lo, s.center - s.radius);
        hi = glm::max(hi, s.center + s.radius);
    }
    frameCamera(lo, hi);
    resolveLamps((lo + hi) * 0.5f);

    const std::vector<std::string> lines = m_warnings.lines();
    for (const std::string& line : lines) {
        std::fprintf(stderr, "vkpath: warning: %s: %s\n", m_file.c_str(), line.c_str());
        if (warningLines) warningLines->push_back(fmt::format("{}: {}", m_file, line));
    }
    return std::move(m_scene);
}

}  // namespace

Scene loadCollada(const std::filesystem::path& path, const LoadOptions& options,
                  std::vector<std::string>* warnings) {
    return ColladaLoader(path, options).load(warnings);
}

}  // namespace vkpath::scene
