#include "scene/mitsuba_export.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <pugixml.hpp>
#include <stdexcept>
#include <vector>

#include "image/image.h"
#include "scene/camera.h"
#include "shared/microfacet.h"

namespace vkpath::scene {
namespace {

namespace fs = std::filesystem;

// The PLY files are written as binary_little_endian straight from memory.
static_assert(std::endian::native == std::endian::little,
              "export-mitsuba writes PLY from memory: little-endian only");

// Nine significant digits: a float survives the round trip through text.
std::string num(float v) {
    return fmt::format("{:.9g}", v);
}
std::string rgb(const glm::vec3& v) {
    return fmt::format("{:.9g}, {:.9g}, {:.9g}", v.x, v.y, v.z);
}

// A name that is safe in a file name and an XML id.
std::string safeName(const std::string& name) {
    std::string out;
    for (char c : name.substr(0, 40))
        out += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
    return out;
}

pugi::xml_node child(pugi::xml_node parent, const char* tag, const std::string& name = "") {
    pugi::xml_node node = parent.append_child(tag);
    if (!name.empty()) node.append_attribute("name") = name.c_str();
    return node;
}

void addValue(pugi::xml_node parent, const char* tag, const std::string& name,
              const std::string& value) {
    child(parent, tag, name).append_attribute("value") = value.c_str();
}

void addRgb(pugi::xml_node parent, const std::string& name, const glm::vec3& value) {
    addValue(parent, "rgb", name, rgb(value));
}

void addXyz(pugi::xml_node parent, const char* tag, const std::string& name, const glm::vec3& v) {
    pugi::xml_node node = child(parent, tag, name);
    node.append_attribute("x") = num(v.x).c_str();
    node.append_attribute("y") = num(v.y).c_str();
    node.append_attribute("z") = num(v.z).c_str();
}

void addLookAt(pugi::xml_node transform, const glm::vec3& origin, const glm::vec3& target,
               const glm::vec3& up) {
    pugi::xml_node lookat = transform.append_child("lookat");
    lookat.append_attribute("origin") = rgb(origin).c_str();
    lookat.append_attribute("target") = rgb(target).c_str();
    lookat.append_attribute("up") = rgb(up).c_str();
}

// Binary PLY: positions, the per-vertex normals when the mesh has them, and
// triangles as lists of three int indices.
void writePly(const fs::path& path, const Mesh& mesh) {
    const bool normals = mesh.normals.size() == mesh.positions.size();
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment vkpath export-mitsuba\n";
    header +=
        fmt::format("element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
                    mesh.positions.size());
    if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
    header += fmt::format("element face {}\nproperty list uchar int vertex_indices\nend_header\n",
                          mesh.triangles.size());

    std::ofstream out(path, std::ios::binary);
    out.write(header.data(), std::streamsize(header.size()));
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        out.write(reinterpret_cast<const char*>(&mesh.positions[i]), sizeof(glm::vec3));
        if (normals) out.write(reinterpret_cast<const char*>(&mesh.normals[i]), sizeof(glm::vec3));
    }
    for (const glm::uvec3& t : mesh.triangles) {
        const char count = 3;
        out.write(&count, 1);
        const int32_t indices[3] = {int32_t(t.x), int32_t(t.y), int32_t(t.z)};
        out.write(reinterpret_cast<const char*>(indices), sizeof(indices));
    }
    if (!out.flush()) throw std::runtime_error(fmt::format("{}: cannot write", path.string()));
}

// The grid medium's voxels as a Mitsuba grid volume (.vol, version 3:
// "VOL", 3, encoding 1 = float32, the resolution, one channel, the box, then
// the values with x fastest).
void writeVol(const fs::path& path, const VolumeGrid& grid) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(fmt::format("{}: cannot write", path.string()));
    auto put = [&](auto value) { out.write(reinterpret_cast<const char*>(&value), sizeof(value)); };
    out.write("VOL", 3);
    put(uint8_t(3));
    put(int32_t(1));
    put(int32_t(grid.resolution.x));
    put(int32_t(grid.resolution.y));
    put(int32_t(grid.resolution.z));
    put(int32_t(1));
    const glm::dvec3 hi = grid.origin + glm::dvec3(grid.resolution - 1u) * grid.voxelSize;
    for (double v : {grid.origin.x, grid.origin.y, grid.origin.z, hi.x, hi.y, hi.z}) put(float(v));
    out.write(reinterpret_cast<const char*>(grid.density->data()),
              std::streamsize(grid.density->size() * sizeof(float)));
    if (!out.flush()) throw std::runtime_error(fmt::format("{}: cannot write", path.string()));
}

// A `to_world` of a scale and a translation under `parent`.
void addScaleTranslate(pugi::xml_node parent, const glm::dvec3& scale, const glm::dvec3& offset) {
    pugi::xml_node transform = child(parent, "transform", "to_world");
    pugi::xml_node s = transform.append_child("scale");
    s.append_attribute("x") = num(float(scale.x)).c_str();
    s.append_attribute("y") = num(float(scale.y)).c_str();
    s.append_attribute("z") = num(float(scale.z)).c_str();
    pugi::xml_node t = transform.append_child("translate");
    t.append_attribute("x") = num(float(offset.x)).c_str();
    t.append_attribute("y") = num(float(offset.y)).c_str();
    t.append_attribute("z") = num(float(offset.z)).c_str();
}

// The grid medium as Mitsuba's `heterogeneous` medium over a `gridvolume`
// (whose unit cube holds the voxels' cells, each value at its cell's centre:
// voxel i at origin + i voxelSize, as vkpath's) inside a `cube` of `null`
// BSDF around the voxels' cells, the fog its exterior where there is fog.
void addGridMedium(pugi::xml_node root, const Scene& s, const fs::path& outDir,
                   MitsubaExportResult& result) {
    const VolumeGrid& grid = *s.volume;
    writeVol(outDir / "volume.vol", grid);
    result.files.push_back(outDir / "volume.vol");
    pugi::xml_node medium = root.append_child("medium");
    medium.append_attribute("type") = "heterogeneous";
    medium.append_attribute("id") = "volume";
    pugi::xml_node sigmaT = child(medium, "volume", "sigma_t");
    sigmaT.append_attribute("type") = "gridvolume";
    addValue(sigmaT, "string", "filename", "volume.vol");
    const glm::dvec3 size = glm::dvec3(grid.resolution) * grid.voxelSize;
    const glm::dvec3 corner = grid.origin - 0.5 * grid.voxelSize;
    addScaleTranslate(sigmaT, size, corner);
    addValue(medium, "float", "scale", num(grid.densityScale));
    addRgb(medium, "albedo", grid.albedo);
    pugi::xml_node phase = medium.append_child("phase");
    phase.append_attribute("type") = "hg";
    addValue(phase, "float", "g", num(grid.anisotropy));
    pugi::xml_node cube = root.append_child("shape");
    cube.append_attribute("type") = "cube";
    cube.append_attribute("id") = "volume_bounds";
    addScaleTranslate(cube, 0.5 * size, corner + 0.5 * size);
    cube.append_child("bsdf").append_attribute("type") = "null";
    pugi::xml_node interior = cube.append_child("ref");
    interior.append_attribute("name") = "interior";
    interior.append_attribute("id") = "volume";
    if (s.fog.present()) {
        pugi::xml_node exterior = cube.append_child("ref");
        exterior.append_attribute("name") = "exterior";
        exterior.append_attribute("id") = "fog";
        result.warnings.push_back(
            "the grid medium (--volume) with fog: vkpath adds the two inside the grid's box, "
            "Mitsuba has the grid alone there (a shape's interior is one medium)");
    }
}

// The kinds of a scene's materials that Mitsuba renders differently, each
// reported once by exportMitsuba.
struct MaterialNotes {
    size_t separableMasking =
        0;  // GGX lobes: Mitsuba's G1 G1 against vkpath's height-correlated G2
    size_t schlickConductors = 0;
    size_t metallicRoughness = 0;
    size_t thinWalls = 0;
};

// Mitsuba's GGX parameters for vkpath's roughness (alpha = roughness^2), with
// visible-normal sampling as vkpath's.
void addGgx(pugi::xml_node bsdf, float roughness) {
    addValue(bsdf, "string", "distribution", "ggx");
    addValue(bsdf, "float", "alpha", num(roughness * roughness));
    addValue(bsdf, "boolean", "sample_visible", "true");
}

// vkpath's microfacet lobes are their delta limits below this alpha
// (VKP_MICROFACET_SMOOTH_ALPHA, shared/microfacet.h): Mitsuba's smooth BSDFs.
bool smoothLobe(float roughness) {
    return roughness * roughness < VKP_MICROFACET_SMOOTH_ALPHA;
}

// vkpath's diffuse, mirror, conductor and metallic-roughness surfaces reflect
// on both sides (shared/lobes.h, shared/microfacet.h); Mitsuba's only on the
// front unless wrapped in `twosided`. The dielectrics are one-sided in both:
// the normal tells inside from outside. This is the inside of Mitsuba's
// `twosided` wrapper named `id`.
pugi::xml_node twoSided(pugi::xml_node scene, const std::string& id) {
    pugi::xml_node twosided = scene.append_child("bsdf");
    twosided.append_attribute("type") = "twosided";
    twosided.append_attribute("id") = id.c_str();
    return twosided.append_child("bsdf");
}

// One case per material kind (no default: a new kind fails to compile
// until it has an export or a note).
void addMaterial(pugi::xml_node scene, const Material& m, const std::string& id,
                 MaterialNotes& notes) {
    switch (m.kind) {
        case MaterialKind::Dielectric:
        case MaterialKind::RoughDielectric: {
            if (m.thinWalled) {
                // Mitsuba's thin dielectric (smooth only; reported).
                pugi::xml_node bsdf = scene.append_child("bsdf");
                bsdf.append_attribute("type") = "thindielectric";
                bsdf.append_attribute("id") = id.c_str();
                addValue(bsdf, "float", "int_ior", num(m.ior));
                addValue(bsdf, "float", "ext_ior", "1");
                addRgb(bsdf, "specular_reflectance", m.reflectance);
                addRgb(bsdf, "specular_transmittance", m.transmittance);
                ++notes.thinWalls;
                return;
            }
            const bool rough = m.kind == MaterialKind::RoughDielectric && !smoothLobe(m.roughness);
            pugi::xml_node bsdf = scene.append_child("bsdf");
            bsdf.append_attribute("type") = rough ? "roughdielectric" : "dielectric";
            bsdf.append_attribute("id") = id.c_str();
            if (rough) {
                addGgx(bsdf, m.roughness);
                ++notes.separableMasking;
            }
            addValue(bsdf, "float", "int_ior", num(m.ior));
            addValue(bsdf, "float", "ext_ior",
                     "1");  // Mitsuba's default is air (1.000277); vkpath's is 1
            addRgb(bsdf, "specular_reflectance", m.reflectance);
            addRgb(bsdf, "specular_transmittance", m.transmittance);
            return;
        }
        case MaterialKind::Mirror: {
            // material "none": a perfect conductor (Fresnel reflectance 1), tinted.
            pugi::xml_node bsdf = twoSided(scene, id);
            bsdf.append_attribute("type") = "conductor";
            addValue(bsdf, "string", "material", "none");
            addRgb(bsdf, "specular_reflectance", m.reflectance);
            return;
        }
        case MaterialKind::Conductor: {
            pugi::xml_node bsdf = twoSided(scene, id);
            const bool rough = !smoothLobe(m.roughness);
            bsdf.append_attribute("type") = rough ? "roughconductor" : "conductor";
            if (rough) {
                addGgx(bsdf, m.roughness);
                ++notes.separableMasking;
            }
            if (m.conductorEta != glm::vec3(0.0f)) {
                addRgb(bsdf, "eta", m.conductorEta);
                addRgb(bsdf, "k", m.conductorK);
            } else {
                // Mitsuba's conductors have no Schlick Fresnel: the perfect
                // conductor tinted by F0 (reported).
                addValue(bsdf, "string", "material", "none");
                addRgb(bsdf, "specular_reflectance", m.reflectance);
                ++notes.schlickConductors;
            }
            return;
        }
        case MaterialKind::MetallicRoughness: {
            // The nearest Mitsuba has: its Disney-style `principled` (reported).
            pugi::xml_node bsdf = twoSided(scene, id);
            bsdf.append_attribute("type") = "principled";
            addRgb(bsdf, "base_color", m.reflectance);
            addValue(bsdf, "float", "roughness", num(m.roughness));
            addValue(bsdf, "float", "metallic", num(m.metallic));
            addValue(bsdf, "float", "eta", num(m.ior));
            ++notes.metallicRoughness;
            return;
        }
        case MaterialKind::Diffuse: {
            pugi::xml_node bsdf = twoSided(scene, id);
            bsdf.append_attribute("type") = "diffuse";
            addRgb(bsdf, "reflectance", m.reflectance);
            return;
        }
    }
}

// Whether material `m` has a medium inside: a transmitting kind that
// attenuates (KHR_materials_volume; scattering with volume_scatter).
bool hasInsideMedium(const Material& m) {
    return (materialKindInfo(m.kind).flags & VKP_KIND_TRANSMITS) != 0 &&
           m.attenuation != glm::vec3(0.0f);
}

// A homogeneous medium `id` of attenuation sigma_t, single-scattering albedo
// and Henyey-Greenstein g, as Mitsuba's `homogeneous` (sigma_t x scale and
// albedo, per scene unit) with an `hg` phase function.
void addMedium(pugi::xml_node root, const std::string& id, const glm::vec3& sigmaT,
               const glm::vec3& albedo, float g) {
    pugi::xml_node medium = root.append_child("medium");
    medium.append_attribute("type") = "homogeneous";
    medium.append_attribute("id") = id.c_str();
    // Mitsuba reads an RGB sigma_t as a reflectance, in [0, 1]: its colour
    // over the largest channel, times that channel as `scale`.
    const float largest = std::max(std::max(sigmaT.x, sigmaT.y), sigmaT.z);
    addRgb(medium, "sigma_t", largest > 0.0f ? sigmaT / largest : sigmaT);
    addValue(medium, "float", "scale", num(largest > 0.0f ? largest : 1.0f));
    addRgb(medium, "albedo", albedo);
    pugi::xml_node phase = medium.append_child("phase");
    phase.append_attribute("type") = "hg";
    addValue(phase, "float", "g", num(g));
}

// The media of a scene with any (the fog, the insides of transmitting
// materials): Mitsuba's `volpath` tracks a ray's medium by the shapes'
// interior and exterior media, so every shape's exterior is the fog and
// each transmitting shape's interior its own medium, as vkpath reads a
// segment's medium off its end (shared/path/media.h).
bool hasMedia(const Scene& s) {
    return s.fog.present() || s.volume ||
           std::any_of(s.materials.begin(), s.materials.end(), hasInsideMedium);
}

// The material reference, the media and the area emitter of a shape of
// `material`.
void finishShape(pugi::xml_node shape, const Scene& scene, uint32_t material) {
    child(shape, "ref").append_attribute("id") = fmt::format("mat{}", material).c_str();
    if (material < scene.materials.size() && hasInsideMedium(scene.materials[material])) {
        pugi::xml_node interior = shape.append_child("ref");
        interior.append_attribute("name") = "interior";
        interior.append_attribute("id") = fmt::format("inside{}", material).c_str();
    }
    if (scene.fog.present()) {
        pugi::xml_node exterior = shape.append_child("ref");
        exterior.append_attribute("name") = "exterior";
        exterior.append_attribute("id") = "fog";
    }
    if (material < scene.materials.size() && scene.materials[material].emissive()) {
        pugi::xml_node emitter = shape.append_child("emitter");
        emitter.append_attribute("type") = "area";
        addRgb(emitter, "radiance", scene.materials[material].emission);
    }
}

// Bounds of the geometry, for the sensor's clip planes.
void sceneBounds(const Scene& scene, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = -lo;
    for (const Mesh& mesh : scene.meshes)
        if (!mesh.instanced)
            for (const glm::vec3& p : mesh.positions) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
    if (!scene.instances.empty()) {
        const Bounds placed = scene.geometryBounds();
        lo = glm::min(lo, placed.lo);
        hi = glm::max(hi, placed.hi);
    }
    for (const Sphere& s : scene.spheres) {
        lo = glm::min(lo, s.center - s.radius);
        hi = glm::max(hi, s.center + s.radius);
    }
}

void addSensor(pugi::xml_node scene, const Scene& s, const MitsubaExportSettings& settings) {
    // The kernels' camera frame (makeGpuCamera widens the narrower axis to
    // the film), so the exported field of view is the one vkpath renders.
    const shared::Camera gpu = makeGpuCamera(s.camera, settings.width, settings.height);
    const float tanX = glm::length(gpu.right);
    pugi::xml_node sensor = scene.append_child("sensor");
    sensor.append_attribute("type") = "perspective";
    addValue(sensor, "string", "fov_axis", "x");
    addValue(sensor, "float", "fov", num(glm::degrees(2.0f * std::atan(tanX))));

    // vkpath has no clip planes; Mitsuba needs them. Far: twice the distance
    // to the farthest corner of the geometry's bounds; near: a millionth of it.
    glm::vec3 lo, hi;
    sceneBounds(s, lo, hi);
    float farthest = 1.0f;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                          (corner & 4) ? hi.z : lo.z);
        farthest = std::max(farthest, glm::length(p - gpu.origin));
    }
    addValue(sensor, "float", "near_clip", num(2.0f * farthest * 1e-6f));
    addValue(sensor, "float", "far_clip", num(2.0f * farthest));

    pugi::xml_node transform = child(sensor, "transform", "to_world");
    addLookAt(transform, gpu.origin, gpu.origin + gpu.forward, glm::normalize(gpu.up));

    // Independent uniform samples, as vkpath draws them (shared/rng.h).
    pugi::xml_node sampler = sensor.append_child("sampler");
    sampler.append_attribute("type") = "independent";
    addValue(sampler, "integer", "sample_count", std::to_string(settings.samplesPerPixel));
    addValue(sampler, "integer", "seed", std::to_string(settings.seed));

    pugi::xml_node film = sensor.append_child("film");
    film.append_attribute("type") = "hdrfilm";
    addValue(film, "integer", "width", std::to_string(settings.width));
    addValue(film, "integer", "height", std::to_string(settings.height));
    addValue(film, "string", "pixel_format", "rgb");
    addValue(film, "string", "component_format", "float32");
    // vkpath jitters each sample inside its own pixel and averages: a box of one pixel.
    film.append_child("rfilter").append_attribute("type") = "box";
}

void addLights(pugi::xml_node root, const Scene& s) {
    for (const PointLight& light : s.pointLights) {
        pugi::xml_node e = root.append_child("emitter");
        e.append_attribute("type") = "point";
        addXyz(e, "point", "position", light.position);
        addRgb(e, "intensity", light.intensity);
    }
    for (const SpotLight& light : s.spotLights) {
        pugi::xml_node e = root.append_child("emitter");
        e.append_attribute("type") = "spot";
        // Mitsuba's spot points along its local +Z; any up not along the axis will do.
        const glm::vec3 up =
            std::abs(light.direction.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        addLookAt(child(e, "transform", "to_world"), light.position,
                  light.position + light.direction, up);
        addRgb(e, "intensity", light.intensity);
        addValue(e, "float", "cutoff_angle", num(glm::degrees(light.outerConeAngle)));
        addValue(e, "float", "beam_width", num(glm::degrees(light.innerConeAngle)));
    }
    for (const DirectionalLight& light : s.directionalLights) {
        pugi::xml_node e = root.append_child("emitter");
        e.append_attribute("type") = "directional";
        addXyz(e, "vector", "direction", light.direction);
        addRgb(e, "irradiance", light.irradiance);
    }
}

}  // namespace

MitsubaExportResult exportMitsuba(const Scene& s, const MitsubaExportSettings& settings,
                                  const fs::path& outDir) {
    pugi::xml_document doc;
    pugi::xml_node root = doc.append_child("scene");
    root.append_attribute("version") = "3.0.0";

    // Mitsuba's max_depth counts path segments (1: emitters seen directly),
    // vkpath's -m bounces (0: emitters seen directly): one more. Both start
    // Russian roulette after the same vertex (the rr_depth-th hit).
    pugi::xml_node integrator = root.append_child("integrator");
    integrator.append_attribute("type") = hasMedia(s) ? "volpath" : "path";
    addValue(integrator, "integer", "max_depth", std::to_string(settings.maxDepth + 1));
    addValue(integrator, "integer", "rr_depth", std::to_string(settings.rouletteDepth));
    // (declared before the sensor that refers to it)
    if (s.fog.present()) {
        const glm::vec3 sigmaT = s.fog.scattering + s.fog.absorption;
        addMedium(root, "fog", sigmaT,
                  glm::vec3(sigmaT.x > 0 ? s.fog.scattering.x / sigmaT.x : 0.0f,
                            sigmaT.y > 0 ? s.fog.scattering.y / sigmaT.y : 0.0f,
                            sigmaT.z > 0 ? s.fog.scattering.z / sigmaT.z : 0.0f),
                  s.fog.anisotropy);
    }
    addSensor(root, s,
              settings);  // before any file is written: it checks the camera and film

    MitsubaExportResult result;
    fs::create_directories(outDir / "meshes");

    // The camera sits in the fog (vkpath's camera rays start in it).
    if (s.fog.present()) child(root.child("sensor"), "ref").append_attribute("id") = "fog";
    MaterialNotes notes;
    for (size_t i = 0; i < s.materials.size(); ++i) {
        addMaterial(root, s.materials[i], fmt::format("mat{}", i), notes);
        if (hasInsideMedium(s.materials[i]))
            addMedium(root, fmt::format("inside{}", i), s.materials[i].attenuation,
                      s.materials[i].scatteringAlbedo, s.materials[i].scatterAnisotropy);
    }

    if (s.volume) addGridMedium(root, s, outDir, result);
    size_t normalMapped = 0;
    // A mesh as a PLY shape, under `parent` (the scene, or a shape group).
    auto addMesh = [&](pugi::xml_node parent, size_t i) {
        const Mesh& mesh = s.meshes[i];
        if (mesh.triangles.empty()) return;
        const std::string id = fmt::format("mesh{:03}_{}", i, safeName(mesh.name));
        const fs::path file = fs::path("meshes") / (id + ".ply");
        writePly(outDir / file, mesh);
        result.files.push_back(outDir / file);
        pugi::xml_node shape = parent.append_child("shape");
        shape.append_attribute("type") = "ply";
        shape.append_attribute("id") = id.c_str();
        addValue(shape, "string", "filename", file.generic_string());
        // vkpath interpolates vertex normals where a mesh has them (and shades
        // flat triangles with their face normal, which interpolating equal
        // normals gives too); without them both use face normals.
        addValue(shape, "boolean", "face_normals", mesh.normals.empty() ? "true" : "false");
        finishShape(shape, s, mesh.material);
        normalMapped += mesh.material < s.materials.size() &&
                        s.materials[mesh.material].normalTexture.present();
    };
    for (size_t i = 0; i < s.meshes.size(); ++i)
        if (!s.meshes[i].instanced) addMesh(root, i);
    // Instanced meshes: each placed range once, as a Mitsuba shape group,
    // and an instance shape per placement with its matrix (row by row).
    std::map<std::pair<uint32_t, uint32_t>, std::string> groups;
    for (const Instance& instance : s.instances) {
        const auto key = std::pair(instance.firstMesh, instance.meshCount);
        if (!groups.contains(key)) {
            const std::string id = fmt::format("object{:03}", groups.size());
            pugi::xml_node group = root.append_child("shape");
            group.append_attribute("type") = "shapegroup";
            group.append_attribute("id") = id.c_str();
            for (uint32_t m = instance.firstMesh; m < instance.firstMesh + instance.meshCount; ++m)
                addMesh(group, m);
            groups[key] = id;
        }
        pugi::xml_node shape = root.append_child("shape");
        shape.append_attribute("type") = "instance";
        child(shape, "ref").append_attribute("id") = groups[key].c_str();
        std::vector<std::string> entries;
        for (int row = 0; row < 4; ++row)
            for (int column = 0; column < 4; ++column)
                entries.push_back(num(float(instance.objectToWorld[column][row])));
        const std::string matrix = fmt::format("{}", fmt::join(entries, " "));
        child(shape, "transform", "to_world").append_child("matrix").append_attribute("value") =
            matrix.c_str();
    }
    size_t emissiveSpheres = 0;
    for (size_t i = 0; i < s.spheres.size(); ++i) {
        const Sphere& sphere = s.spheres[i];
        pugi::xml_node shape = root.append_child("shape");
        shape.append_attribute("type") = "sphere";
        shape.append_attribute("id") =
            fmt::format("sphere{:03}_{}", i, safeName(sphere.name)).c_str();
        addXyz(shape, "point", "center", sphere.center);
        addValue(shape, "float", "radius", num(sphere.radius));
        finishShape(shape, s, sphere.material);
        emissiveSpheres +=
            sphere.material < s.materials.size() && s.materials[sphere.material].emissive();
    }
    addLights(root, s);

    if (s.environment) {
        const Environment& env = *s.environment;
        pugi::xml_node e = root.append_child("emitter");
        if (env.map) {
            // The texels vkpath renders with (after its own clamping), in the
            // same equirectangular orientation: Mitsuba's envmap maps a
            // direction d to u = atan2(d.x, -d.z) / 2 pi, v = acos(d.y) / pi,
            // exactly as shared/environment_map.h does. vkpath's rotation is
            // world = R_y(angle) map, Mitsuba's to_world rotation the same.
            image::writeExr(outDir / "envmap.exr", *env.map);
            result.files.push_back(outDir / "envmap.exr");
            e.append_attribute("type") = "envmap";
            addValue(e, "string", "filename", "envmap.exr");
            addValue(e, "float", "scale", num(env.strength));
            pugi::xml_node rotate = child(e, "transform", "to_world").append_child("rotate");
            rotate.append_attribute("y") = "1";
            rotate.append_attribute("angle") = num(env.rotationDegrees).c_str();
            result.warnings.push_back(
                "environment map: both interpolate bilinearly, but Mitsuba 3.9 places the map's "
                "rows at "
                "v = j / (height - 1), vkpath at the texel centres (j + 0.5) / height: the sky "
                "shifts by up to "
                "half a texel in elevation (docs/TRADEOFFS.md)");
        } else {
            e.append_attribute("type") = "constant";
            addRgb(e, "radiance", env.color * env.strength);
        }
    }

    const auto ranged = [](const auto& light) { return light.range > 0.0f; };
    if (std::any_of(s.pointLights.begin(), s.pointLights.end(), ranged) ||
        std::any_of(s.spotLights.begin(), s.spotLights.end(), ranged))
        result.warnings.push_back(
            "point and spot lights with a range (KHR_lights_punctual): Mitsuba's fall off with the "
            "inverse square forever, vkpath's reach nothing beyond their range");
    if (!s.spotLights.empty())
        result.warnings.push_back(
            fmt::format("spot lights: Mitsuba's falloff is linear in angle from beam_width (inner "
                        "cone) to cutoff_angle "
                        "(outer cone), vkpath's is KHR_lights_punctual's squared ramp in cosine: "
                        "the cones' edges differ "
                        "({} spot lights)",
                        s.spotLights.size()));
    if (notes.separableMasking > 0)
        result.warnings.push_back(
            fmt::format("rough conductors and dielectrics: written as Mitsuba's roughconductor / "
                        "roughdielectric with GGX, "
                        "the same alpha and visible-normal sampling, but Mitsuba masks with the "
                        "separable G1(wo) G1(wi), "
                        "vkpath with the height-correlated G2 (Heitz 2014): Mitsuba's rough "
                        "surfaces are slightly darker "
                        "({} materials)",
                        notes.separableMasking));
    if (notes.schlickConductors > 0)
        result.warnings.push_back(
            fmt::format("conductors with Schlick's Fresnel (glTF metals, F0 = base colour): "
                        "Mitsuba has no Schlick conductor; "
                        "written as its perfect conductor tinted by F0, whose reflectance does not "
                        "rise toward 1 at grazing "
                        "angles ({} materials)",
                        notes.schlickConductors));
    if (notes.thinWalls > 0)
        result.warnings.push_back(fmt::format(
            "thin-walled glass (glTF transmission without a volume): written as Mitsuba's "
            "thindielectric, which is smooth and adds the light reflected back and forth inside "
            "the wall (vkpath, as glTF, has one interface; a rough wall's blur is lost) "
            "({} materials)",
            notes.thinWalls));
    if (notes.metallicRoughness > 0)
        result.warnings.push_back(
            fmt::format("glTF metallic-roughness materials: written as Mitsuba's principled BSDF "
                        "(base colour, metallic, "
                        "roughness, eta), whose diffuse lobe (Disney's, with retro-reflection), "
                        "Fresnel and masking differ "
                        "from glTF 2.0 Appendix B's, and which has no KHR_materials_specular "
                        "weight or colour ({} materials)",
                        notes.metallicRoughness));
    // What the export leaves out of a material: its textures (the factors are
    // written alone) and its alpha (written opaque).
    size_t textured = 0, alphaCovered = 0, layered = 0, anisotropic = 0, dispersive = 0;
    for (const Material& m : s.materials) {
        anisotropic += m.anisotropy > 0.0f;
        dispersive += m.dispersion > 0.0f;
        layered += m.clearcoat > 0.0f || m.sheenColor != glm::vec3(0.0f) ||
                   m.diffuseTransmission > 0.0f || m.iridescence > 0.0f;
        textured += m.baseColorTexture.present() || m.emissiveTexture.present() ||
                    m.metallicRoughnessTexture.present();
        alphaCovered += m.alphaMode != AlphaMode::Opaque;
    }
    if (textured > 0)
        result.warnings.push_back(
            fmt::format("base-colour, emissive and metallic-roughness textures are not exported: "
                        "Mitsuba renders those materials with their factors alone ({} materials)",
                        textured));
    if (layered > 0)
        result.warnings.push_back(
            fmt::format("clear coats, sheens, diffuse transmission and thin films "
                        "(KHR_materials_clearcoat, KHR_materials_sheen, "
                        "KHR_materials_diffuse_transmission, KHR_materials_iridescence) are not "
                        "exported: Mitsuba's principled BSDF has Disney's coat and sheen and "
                        "neither of the others; those materials are written without them ({} "
                        "materials)",
                        layered));
    if (anisotropic > 0)
        result.warnings.push_back(
            fmt::format("anisotropy (KHR_materials_anisotropy) is not exported: Mitsuba's "
                        "alpha_u and alpha_v follow its own surface parametrisation, not glTF's "
                        "tangents and rotation; those materials are written isotropic ({} "
                        "materials)",
                        anisotropic));
    if (dispersive > 0)
        result.warnings.push_back(
            fmt::format("dispersion (KHR_materials_dispersion) is not exported: Mitsuba's RGB "
                        "dielectric has one index; those materials are written with their "
                        "index at 587.6 nm ({} materials)",
                        dispersive));
    if (alphaCovered > 0)
        result.warnings.push_back(
            fmt::format("alpha (glTF alphaMode MASK and BLEND) is not exported: Mitsuba renders "
                        "those surfaces opaque ({} materials)",
                        alphaCovered));
    if (normalMapped > 0)
        result.warnings.push_back(
            fmt::format("normal maps are not exported: Mitsuba shades those meshes with their "
                        "vertex normals ({} meshes)",
                        normalMapped));
    if (emissiveSpheres > 0)
        result.warnings.push_back(
            fmt::format("emissive spheres: Mitsuba's emit outward only, vkpath's to both sides "
                        "(the same unless something "
                        "sees a sphere from inside; {} spheres)",
                        emissiveSpheres));

    result.xml = outDir / "scene.xml";
    if (!doc.save_file(result.xml.c_str(), "    "))
        throw std::runtime_error(fmt::format("{}: cannot write", result.xml.string()));
    result.files.push_back(result.xml);
    return result;
}

}  // namespace vkpath::scene
