#include "wavefront/gpu_scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <numbers>
#include <span>
#include <type_traits>

#include "albedo/albedo_tables.h"
#include "input_error.h"
#include "scene/alias_table.h"
#include "scene/environment_table.h"
#include "shared/bsdf.h"
#include "vk/context.h"

namespace vkpath::wavefront {
namespace {

constexpr double PI = std::numbers::pi;

shared::Material toGpu(const scene::Material& m, uint32_t textures = VKP_NO_TEXTURE) {
    shared::Material g{};  // (zero padding)
    g.textures = textures;
    g.reflectance = m.reflectance;
    g.kind = static_cast<uint32_t>(m.kind);
    g.transmittance = m.transmittance;
    g.ior = m.ior;
    g.emission = m.emission;
    g.roughness = m.roughness;
    g.metallic = m.metallic;
    g.specular = m.specular;
    g.flags = 0;
    const bool glass = (scene::materialKindInfo(m.kind).flags & VKP_KIND_TRANSMITS) != 0;
    g.attenuation = glass && !m.thinWalled ? m.attenuation : glm::vec3(0.0f);
    if (glass && m.thinWalled) g.flags = VKP_MATERIAL_THIN_WALLED;
    if (glass && !m.thinWalled) g.dispersion = m.dispersion;
    if (m.kind == scene::MaterialKind::Conductor && m.conductorEta != glm::vec3(0.0f)) {
        g.flags = VKP_MATERIAL_COMPLEX_FRESNEL;
        g.reflectance = m.conductorEta;
        g.transmittance = m.conductorK;
    }
    if ((scene::materialKindInfo(m.kind).flags & VKP_KIND_MICROFACET) != 0 && m.anisotropy > 0.0f) {
        g.anisotropy = m.anisotropy;
        g.anisotropyDirection =
            glm::vec3(std::cos(m.anisotropyRotation), std::sin(m.anisotropyRotation), 0.0f);
    }
    if (m.kind == scene::MaterialKind::MetallicRoughness) {
        // The dielectric layer's Fresnel at normal incidence (KHR_materials_specular,
        // "Implementation"): min(((ior - 1) / (ior + 1))^2 specularColor, 1) x specular.
        const float r = (m.ior - 1.0f) / (m.ior + 1.0f);
        g.transmittance = glm::min(r * r * m.specularColor, glm::vec3(1.0f)) * m.specular;
        g.sheenColor = m.sheenColor;
        g.sheenRoughness = m.sheenRoughness;
        g.clearcoat = m.clearcoat;
        g.clearcoatRoughness = m.clearcoatRoughness;
        g.diffuseTransmission = m.diffuseTransmission;
        g.diffuseTransmissionColor = m.diffuseTransmissionColor;
        g.iridescence = m.iridescence;
        g.iridescenceIor = m.iridescenceIor;
        g.iridescenceThicknessMinimum = m.iridescenceThicknessMinimum;
        g.iridescenceThickness = m.iridescenceThicknessMaximum;
    }
    return g;
}

shared::Medium toGpu(const scene::Medium& m) {
    shared::Medium g{};  // (zero padding)
    g.scattering = m.scattering;
    g.absorption = m.absorption;
    g.anisotropy = m.anisotropy;
    return g;
}

// The media array (shared/medium.h): the fog, then the inside of each
// material, a transmitting material's attenuation split by its
// single-scattering albedo; empty unless the fog is present or some inside
// scatters (a glass that only absorbs keeps Beer-Lambert without it:
// shared/path/absorption.h).
std::vector<shared::Medium> buildMedia(const scene::Scene& scene) {
    std::vector<shared::Medium> media{toGpu(scene.fog)};
    bool scatters = scene.fog.present() || scene.volume.has_value();
    for (const scene::Material& m : scene.materials) {
        scene::Medium inside;
        if ((scene::materialKindInfo(m.kind).flags & VKP_KIND_TRANSMITS) && !m.thinWalled) {
            inside.scattering = m.attenuation * m.scatteringAlbedo;
            inside.absorption = m.attenuation - inside.scattering;
            inside.anisotropy = m.scatterAnisotropy;
        }
        scatters = scatters || inside.scattering != glm::vec3(0.0f);
        media.push_back(toGpu(inside));
    }
    return scatters ? media : std::vector<shared::Medium>{};
}

// Voxels per majorant cell along each axis (shared/medium.h GridMedium): a
// 64^3 grid has 8^3 cells.
constexpr uint32_t MAJORANT_CELL = 8;

// The grid medium's record, densities and majorants (render --volume): the
// majorant of a cell is the largest density among the voxels its trilinear
// interpolation reads, those from its first corner to the next cell's.
void buildGridMedium(const scene::VolumeGrid& v, SceneTables& t) {
    shared::GridMedium g{};
    g.origin = glm::vec3(v.origin);
    g.inverseVoxelSize = glm::vec3(1.0 / v.voxelSize);
    g.densityScale = v.densityScale;
    g.albedo = v.albedo;
    g.anisotropy = v.anisotropy;
    g.resolution = v.resolution;
    g.majorantCell = MAJORANT_CELL;
    g.majorantResolution =
        glm::max((v.resolution - glm::uvec3(1) + glm::uvec3(MAJORANT_CELL - 1)) / MAJORANT_CELL,
                 glm::uvec3(1));
    t.gridMedium = {g};
    t.gridDensity = *v.density;
    const glm::uvec3 m = g.majorantResolution;
    t.gridMajorant.assign(size_t(m.x) * m.y * m.z, 0.0f);
    for (uint32_t k = 0; k < v.resolution.z; ++k)
        for (uint32_t j = 0; j < v.resolution.y; ++j)
            for (uint32_t i = 0; i < v.resolution.x; ++i) {
                const float d = v.at(i, j, k);
                if (d == 0.0f) continue;
                // The cells whose corner-to-corner range holds voxel (i, j, k):
                // c M <= index <= (c + 1) M, so c from ceil(index / M) - 1 to index / M.
                const glm::uvec3 index(i, j, k);
                glm::uvec3 first, last;
                for (int a = 0; a < 3; ++a) {
                    last[a] = std::min(index[a] / MAJORANT_CELL, m[a] - 1);
                    first[a] = index[a] % MAJORANT_CELL == 0 && index[a] > 0
                                   ? index[a] / MAJORANT_CELL - 1
                                   : last[a];
                }
                for (uint32_t z = first.z; z <= last.z; ++z)
                    for (uint32_t y = first.y; y <= last.y; ++y)
                        for (uint32_t x = first.x; x <= last.x; ++x) {
                            float& majorant = t.gridMajorant[(size_t(z) * m.y + y) * m.x + x];
                            // (a hair above: trilinear interpolation in float may
                            // round past the largest voxel by an ulp)
                            majorant = std::max(majorant, d * 1.0001f);
                        }
            }
    t.info.gridMedium = 1u;
}

// Centre and radius of a sphere around all geometry.
std::pair<glm::dvec3, double> boundingSphere(const scene::Scene& scene) {
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (const auto& mesh : scene.meshes)
        if (!mesh.instanced)
            for (const glm::vec3& p : mesh.positions)
                if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
                    lo = glm::min(lo, glm::dvec3(p));
                    hi = glm::max(hi, glm::dvec3(p));
                }
    if (!scene.instances.empty()) {  // placed instanced meshes
        const scene::Bounds placed = scene.geometryBounds();
        lo = glm::min(lo, glm::dvec3(placed.lo));
        hi = glm::max(hi, glm::dvec3(placed.hi));
    }
    for (const auto& s : scene.spheres) {
        lo = glm::min(lo, glm::dvec3(s.center) - double(s.radius));
        hi = glm::max(hi, glm::dvec3(s.center) + double(s.radius));
    }
    if (!(lo.x <= hi.x)) return {glm::dvec3(0), 1.0};
    return {(lo + hi) * 0.5, std::max(1e-30, glm::length(hi - lo) * 0.5)};
}

// A light's device record and its power (luminance-weighted watts), by which
// the alias table picks lights: one function per light type.
struct LightEntry {
    shared::Light record{};
    double power = 0;
};

// Emits from its front face only.
// A material whose emission lies under a clear coat (KHR_materials_clearcoat).
bool coated(const scene::Material& m) {
    return m.kind == scene::MaterialKind::MetallicRoughness && m.clearcoat > 0.0f;
}

LightEntry triangleLight(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 emission) {
    LightEntry e;
    e.record.type = VKP_LIGHT_TRIANGLE;
    e.record.p0 = p0;
    e.record.p1 = p1;
    e.record.p2 = p2;
    e.record.emission = emission;
    // As the kernels computed them at every sample before (float, shared/sampling.h).
    e.record.normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    e.record.area = glm::length(shared::triangleArea3(p0, p1, p2));
    const double area = 0.5 * glm::length(glm::cross(glm::dvec3(p1 - p0), glm::dvec3(p2 - p0)));
    e.power = scene::luminance(emission) * area * PI;
    return e;
}

LightEntry sphereLight(const scene::Sphere& s, glm::vec3 emission) {
    LightEntry e;
    e.record.type = VKP_LIGHT_SPHERE;
    e.record.p0 = s.center;
    e.record.radius = s.radius;
    e.record.emission = emission;
    e.power = scene::luminance(emission) * 4.0 * PI * double(s.radius) * s.radius * PI;
    return e;
}

LightEntry pointLight(const scene::PointLight& p) {
    LightEntry e;
    e.record.type = VKP_LIGHT_POINT;
    e.record.p0 = p.position;
    e.record.emission = p.intensity;
    e.record.radius = p.range;
    e.power = 4.0 * PI * scene::luminance(p.intensity);
    return e;
}

LightEntry spotLight(const scene::SpotLight& s) {
    LightEntry e;
    e.record.type = VKP_LIGHT_SPOT;
    e.record.p0 = s.position;
    e.record.p1 = glm::normalize(s.direction);
    e.record.emission = s.intensity;
    e.record.cosInner = std::cos(s.innerConeAngle);
    e.record.cosOuter = std::cos(s.outerConeAngle);
    e.record.radius = s.range;
    e.power = 2.0 * PI * (1.0 - 0.5 * (e.record.cosInner + e.record.cosOuter)) *
              scene::luminance(s.intensity);
    return e;
}

// Its power is what falls on the scene's bounding sphere (radius sceneRadius).
LightEntry directionalLight(const scene::DirectionalLight& d, double sceneRadius) {
    LightEntry e;
    e.record.type = VKP_LIGHT_DIRECTIONAL;
    e.record.p1 = glm::normalize(d.direction);
    e.record.emission = d.irradiance;
    e.power = scene::luminance(d.irradiance) * PI * sceneRadius * sceneRadius;
    return e;
}

// radiantIntensity: the integral of the environment's luminance over the sphere.
LightEntry environmentLight(double radiantIntensity, float strength, double sceneRadius) {
    LightEntry e;
    e.record.type = VKP_LIGHT_ENVIRONMENT;
    e.power = PI * sceneRadius * sceneRadius * radiantIntensity * strength;
    return e;
}

// Bytes of the device buffer that holds `bytes` of an array: whole 16-byte
// texels, at least one, since the kernels read most arrays as texel buffers
// (stages/lib/scene_access.glsl) and an empty array still needs a buffer to
// bind.
uint64_t texelAligned(uint64_t bytes) {
    return std::max<uint64_t>(16, (bytes + 15) / 16 * 16);
}

template <typename T>
vk::Buffer uploadArray(vk::Context& context, const std::vector<T>& data, const char* name) {
    vk::Buffer buffer(context, texelAligned(data.size() * sizeof(T)), vk::MemoryKind::DeviceLocal,
                      name);
    buffer.upload(std::as_bytes(std::span(data)));
    return buffer;
}

}  // namespace

namespace {

// The scene moved by -origin, each coordinate computed in double and rounded
// once: floats near 1e5 minus an origin near 1e5 come out exact.
scene::Scene moved(const scene::Scene& world, glm::dvec3 origin) {
    scene::Scene s = world;
    auto move = [&](glm::vec3& p) { p = glm::vec3(glm::dvec3(p) - origin); };
    for (auto& mesh : s.meshes)
        if (!mesh.instanced)
            for (auto& p : mesh.positions) move(p);
    // Instanced meshes stay in their own space; their placements move.
    for (auto& instance : s.instances)
        instance.objectToWorld = glm::translate(glm::dmat4(1.0), -origin) * instance.objectToWorld;
    for (auto& sphere : s.spheres) move(sphere.center);
    for (auto& light : s.pointLights) move(light.position);
    for (auto& light : s.spotLights) move(light.position);
    move(s.camera.position);
    move(s.camera.target);
    if (s.volume) s.volume->origin -= origin;
    return s;
}

// Whether a material scatters through delta lobes only (no non-delta lobe,
// shared/bsdf.h hasNonDeltaLobe: a mirror, glass, smooth metal) and bends or
// reflects light on the way: a glass of index 1 passes it straight through
// and is left out.
bool smoothSpecular(const shared::Material& m) {
    const bool glass = (shared::materialKindFlags(m.kind) & VKP_KIND_TRANSMITS) != 0;
    return !shared::hasNonDeltaLobe(m) && !(glass && m.ior == 1.0f);
}

// The scene's smooth specular spheres that are not degenerate, largest first
// (ties in scene order), at most VKP_MAX_GUIDE_SPHERES.
std::vector<glm::vec4> guideSpheres(const scene::Scene& scene,
                                    const std::vector<shared::Material>& materials) {
    std::vector<glm::vec4> spheres;
    for (const scene::Sphere& s : scene.spheres)
        if (!bvh::isDegenerateSphere(s.center, s.radius) &&
            smoothSpecular(materials.at(s.material)))
            spheres.emplace_back(s.center, s.radius);
    std::stable_sort(spheres.begin(), spheres.end(),
                     [](const glm::vec4& a, const glm::vec4& b) { return a.w > b.w; });
    if (spheres.size() > VKP_MAX_GUIDE_SPHERES) spheres.resize(VKP_MAX_GUIDE_SPHERES);
    return spheres;
}

// Per material, the kinds of primitive of the BVH that wear it: the
// non-degenerate triangles of the meshes drawn (an instanced mesh is drawn
// when an instance places it) and spheres.
std::vector<uint8_t> materialPrimitives(const scene::Scene& scene, size_t materialCount) {
    std::vector<uint8_t> use(materialCount, 0);
    std::vector<bool> placed(scene.meshes.size(), false);
    for (const scene::Instance& instance : scene.instances)
        for (uint32_t m = instance.firstMesh;
             m < instance.firstMesh + instance.meshCount && m < scene.meshes.size(); ++m)
            placed[m] = true;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const scene::Mesh& mesh = scene.meshes[m];
        if (mesh.instanced && !placed[m]) continue;
        const auto drawn = [&](const glm::uvec3& tri) {
            const size_t n = mesh.positions.size();
            return tri.x < n && tri.y < n && tri.z < n &&
                   !bvh::isDegenerateTriangle(mesh.positions[tri.x], mesh.positions[tri.y],
                                              mesh.positions[tri.z]);
        };
        if (std::any_of(mesh.triangles.begin(), mesh.triangles.end(), drawn))
            use.at(mesh.material) |= MATERIAL_ON_TRIANGLES;
    }
    for (const scene::Sphere& s : scene.spheres)
        if (!bvh::isDegenerateSphere(s.center, s.radius)) use.at(s.material) |= MATERIAL_ON_SPHERES;
    return use;
}

// The light tree over the bounded lights, which come first, and the alias
// table's second part: the tree as a whole, then each light at infinity.
void addLightTree(SceneTables& t, std::span<const double> power) {
    const auto infinite = [](const shared::Light& l) {
        return (shared::lightTypeFlags(l.type) & VKP_LIGHT_IS_INFINITE) != 0u;
    };
    const auto firstInfinite = std::find_if(t.lights.begin(), t.lights.end(), infinite);
    if (!std::all_of(firstInfinite, t.lights.end(), infinite))
        throw std::logic_error("buildSceneTables: a bounded light after one at infinity");
    const size_t bounded = size_t(firstInfinite - t.lights.begin());
    t.lightTree = buildLightTree(std::span(t.lights).first(bounded), power.first(bounded));
    if (t.lightTree.nodes.empty()) return;
    std::vector<double> outside{0.0};
    for (size_t i = 0; i < power.size(); ++i)
        (i < bounded ? outside[0] : outside.emplace_back()) += power[i];
    const std::vector<shared::AliasEntry> second = scene::buildAliasTable(outside);
    t.lightAlias.insert(t.lightAlias.end(), second.begin(), second.end());
}

}  // namespace

void placeCamera(SceneTables& tables, const scene::Camera& world) {
    tables.camera = world;
    tables.camera.position = glm::vec3(glm::dvec3(world.position) - tables.worldOrigin);
    tables.camera.target = glm::vec3(glm::dvec3(world.target) - tables.worldOrigin);
}

SceneTables buildSceneTables(const scene::Scene& world, const bvh::BvhOptions& bvhOptions,
                             const std::function<void(const SceneTables&)>& beforeBvh) {
    SceneTables t;
    t.worldOrigin = boundingSphere(world).first;
    const scene::Scene scene = moved(world, t.worldOrigin);
    t.camera = scene.camera;
    t.surface = buildSurfaceTables(scene);
    t.info.triangleAttributes = t.surface.attributes;
    t.textures = buildTextureTables(scene);
    for (size_t i = 0; i < scene.materials.size(); ++i)
        t.materials.push_back(toGpu(scene.materials[i], t.textures.materialSlots[i]));
    if (t.materials.empty()) t.materials.push_back(toGpu(scene::Material{}));
    t.materialPrimitives = materialPrimitives(scene, t.materials.size());
    t.media = buildMedia(scene);
    t.info.media = t.media.empty() ? 0u : 1u;
    if (scene.volume) buildGridMedium(*scene.volume, t);
    t.materialAlpha = buildMaterialAlpha(scene, t.textures);
    t.info.alphaTested = t.materialAlpha.empty() ? 0u : 1u;
    // The albedo tables of multiple-scattering compensation, for a scene with
    // a GGX lobe that is not a delta (a texture scales the roughness by at
    // most 1: shared/path/textures.h), and of the sheen's albedo scaling.
    const auto rough = [](const shared::Material& m) {
        return (shared::materialKindFlags(m.kind) & VKP_KIND_MICROFACET) != 0 &&
               !shared::microfacetIsSmooth(shared::materialAlpha(m));
    };
    const auto sheen = [](const shared::Material& m) { return m.sheenColor != glm::vec3(0.0f); };
    t.roughLobes = std::any_of(t.materials.begin(), t.materials.end(), rough);
    if (t.roughLobes || std::any_of(t.materials.begin(), t.materials.end(), sheen)) {
        const std::span<const float> table = albedo::microfacetAlbedoTable();
        t.microfacetAlbedo.assign(table.begin(), table.end());
    }

    std::vector<double> power;
    auto addLight = [&](const LightEntry& e) {
        t.lights.push_back(e.record);
        power.push_back(e.power);
    };
    // Emissive surfaces, keyed by (kind, BvhPrimitive::id) for the leaf map.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> surfaceLight;
    uint32_t triangleId = 0;
    for (const auto& mesh : scene.meshes) {
        const scene::Material& m = scene.materials.at(mesh.material);
        for (const glm::uvec3& tri : mesh.triangles) {
            const uint32_t id = triangleId++;
            // A textured emitter is not light-sampled (its emission varies over
            // the triangle, which the light's constant record cannot say): it
            // is found by BSDF samples alone, with weight 1, which is unbiased.
            // So is one with holes (alpha): a light sample could land in one;
            // and one under a clear coat, which dims it by angle.
            const bool holes =
                !t.materialAlpha.empty() && t.materialAlpha[mesh.material].mode != VKP_ALPHA_OPAQUE;
            if (!m.emissive()) continue;
            if (m.emissiveTexture.present() || holes || coated(m)) {
                t.info.unsampledEmitters = 1;
                continue;
            }
            const glm::vec3 p0 = mesh.positions.at(tri.x), p1 = mesh.positions.at(tri.y),
                            p2 = mesh.positions.at(tri.z);
            if (bvh::isDegenerateTriangle(p0, p1, p2)) continue;
            surfaceLight[{VKP_PRIMITIVE_TRIANGLE, id}] = uint32_t(t.lights.size());
            addLight(triangleLight(p0, p1, p2, m.emission));
        }
    }
    for (uint32_t i = 0; i < scene.spheres.size(); ++i) {
        const scene::Sphere& s = scene.spheres[i];
        const scene::Material& m = scene.materials.at(s.material);
        if (!m.emissive() || bvh::isDegenerateSphere(s.center, s.radius)) continue;
        if (coated(m)) {
            t.info.unsampledEmitters = 1;
            continue;
        }
        surfaceLight[{VKP_PRIMITIVE_SPHERE, i}] = uint32_t(t.lights.size());
        addLight(sphereLight(s, m.emission));
    }
    for (const auto& p : scene.pointLights) addLight(pointLight(p));
    for (const auto& s : scene.spotLights) addLight(spotLight(s));
    const auto [center, radius] = boundingSphere(scene);
    for (const auto& d : scene.directionalLights) addLight(directionalLight(d, radius));

    t.info.environmentLight = VKP_NO_LIGHT;
    if (scene.environment) {
        const scene::Environment& env = *scene.environment;
        t.info.hasEnvironment = 1;
        t.info.environment.strength = env.strength;
        t.info.environment.cosRotation = std::cos(glm::radians(env.rotationDegrees));
        t.info.environment.sinRotation = std::sin(glm::radians(env.rotationDegrees));
        t.info.environment.color = env.color;
        double radiantIntensity = 0;  // integral of luminance over the sphere
        if (env.map) {
            t.info.environment.width = env.map->width;
            t.info.environment.height = env.map->height;
            const scene::EnvironmentTable table = scene::buildEnvironmentTable(*env.map);
            t.envAlias = table.entries;
            t.envRadiance.reserve(env.map->pixels.size());
            for (const glm::vec3& texel : env.map->pixels) t.envRadiance.emplace_back(texel, 0.0f);
            // totalWeight integrates luminance x sin(theta) over (u, v), and
            // d omega = 2 pi^2 sin(theta) du dv (shared/environment_map.h).
            radiantIntensity = table.totalWeight * 2 * PI * PI;
            if (t.envAlias.empty()) radiantIntensity = 0;  // a black map is not worth sampling
        } else {
            radiantIntensity = 4 * PI * scene::luminance(env.color);
        }
        if (radiantIntensity > 0 && env.strength > 0) {
            t.info.environmentLight = uint32_t(t.lights.size());
            addLight(environmentLight(radiantIntensity, env.strength, radius));
        }
    }
    t.lightAlias = scene::buildAliasTable(power);
    const bool sampledLights = !t.lightAlias.empty();
    if (!sampledLights) t.lights.clear();  // nothing with power: emission counts fully
    addLightTree(t, power);
    t.info.lightCount = uint32_t(t.lights.size());
    if (t.lights.empty()) t.info.environmentLight = VKP_NO_LIGHT;
    // Guiding finds emissive surfaces through specular spheres, so it is
    // listed where there are some (a constant environment looks the same
    // through a sphere as around it, punctual lights are never hit) and no
    // environment map: a sun in a map is so small and bright that the cone
    // samples turn up its caustics through the spheres far more often while
    // each is still a firefly (docs/TRADEOFFS.md, "Guiding toward specular
    // spheres", measured on material_spheres).
    const bool surfaceEmitters = !surfaceLight.empty() || t.info.unsampledEmitters != 0;
    const bool environmentMap =
        scene.environment && scene.environment->map && scene.environment->strength > 0;
    if (surfaceEmitters && !environmentMap) t.guideSpheres = guideSpheres(scene, t.materials);

    // The BVH last, so that a caller may start on what the rest decides.
    if (beforeBvh) beforeBvh(t);
    t.bvh = bvh::buildBvh(scene, bvhOptions);
    // Every emitter's entry, also where none is a light (the kernels read the
    // entry of each emitter they hit while other lights are sampled).
    if (sampledLights && (!surfaceLight.empty() || t.info.unsampledEmitters != 0)) {
        t.primitiveLight.assign(t.bvh.primitives.size(), VKP_NO_LIGHT);
        for (size_t i = 0; i < t.bvh.primitives.size(); ++i) {
            const auto it = surfaceLight.find({t.bvh.primitives[i].kind, t.bvh.primitives[i].id});
            if (it != surfaceLight.end()) t.primitiveLight[i] = it->second;
        }
    }
    return t;
}

uint64_t deviceBytes(const SceneTables& t) {
    uint64_t bytes = t.bvh.bytes();
#define VKP_ARRAY_BYTES(index, name, Record, access, member) \
    bytes += texelAligned(t.member.size() * sizeof(t.member[0]));
    VKP_SCENE_ARRAYS(VKP_ARRAY_BYTES)
#undef VKP_ARRAY_BYTES
    return bytes;
}

uint64_t GpuScene::bytes() const {
    uint64_t total = bvh.bytes();
#define VKP_BUFFER_BYTES(index, name, Record, access, member) total += name.size();
    VKP_SCENE_ARRAYS(VKP_BUFFER_BYTES)
#undef VKP_BUFFER_BYTES
    return total;
}

std::vector<std::pair<uint32_t, const vk::Buffer*>> GpuScene::bindings() const {
    std::vector<std::pair<uint32_t, const vk::Buffer*>> b = {
        {VKP_WF_BVH_NODES, &bvh.nodeBinding()},
        {VKP_WF_BVH_PRIMITIVES, &bvh.primitiveBinding()},
        {VKP_WF_SCENE_ADDRESSES, &addresses}};
#define VKP_BUFFER_BINDING(index, name, Record, access, member) \
    b.emplace_back(index, VKP_SCENE_ARRAY_SPANS_##access ? &binding(name) : &name);
    VKP_SCENE_ARRAYS(VKP_BUFFER_BINDING)
#undef VKP_BUFFER_BINDING
    return b;
}

GpuScene uploadScene(vk::Context& context, const SceneTables& t, bvh::Traversal traversal) {
    // The arrays that may be read by address, and their sizes.
    std::vector<vk::ArrayExtent> extents;
    for (const vk::ArrayExtent& e : bvh::arrayExtents(t.bvh)) extents.push_back(e);
#define VKP_ARRAY_EXTENT(index, name, Record, access, member) \
    VKP_SCENE_ARRAY_IF_SPANS_##access(                        \
        extents.push_back({#name, t.member.size() * sizeof(t.member[0]), t.member.size()});)
    VKP_SCENE_ARRAYS(VKP_ARRAY_EXTENT)
#undef VKP_ARRAY_EXTENT
    const vk::BufferLimits limits = vk::bufferLimits(context.info());
    GpuScene g;
    g.byAddress = vk::chooseAddressAccess(extents, limits);
    // The BOUND arrays grow with the materials and textures, not the
    // geometry: each must fit one of the device's bindings.
#define VKP_BOUND_FITS(index, name, Record, access, member)                                 \
    if (!VKP_SCENE_ARRAY_SPANS_##access &&                                                  \
        t.member.size() * sizeof(t.member[0]) > limits.deviceBinding)                       \
        throw InputError(fmt::format("scene too large for the device: {} records of " #name \
                                     " do not fit one binding",                             \
                                     t.member.size()));
    VKP_SCENE_ARRAYS(VKP_BOUND_FITS)
#undef VKP_BOUND_FITS
    g.bvh = bvh::uploadBvh(context, t.bvh, g.byAddress);
    if (traversal == bvh::Traversal::RayQuery) {
        std::vector<bool> alphaTested(t.materialAlpha.size());
        for (size_t m = 0; m < t.materialAlpha.size(); ++m)
            alphaTested[m] = t.materialAlpha[m].mode != VKP_ALPHA_OPAQUE;
        bvh::addAccelerationStructures(context, g.bvh, t.bvh, alphaTested);
    }
#define VKP_ARRAY_UPLOAD(index, name, Record, access, member) \
    g.name = uploadArray(context, t.member, #name);
    VKP_SCENE_ARRAYS(VKP_ARRAY_UPLOAD)
#undef VKP_ARRAY_UPLOAD
    shared::SceneAddresses addresses{};
    addresses.bvh = g.bvh.addresses();
    if (g.byAddress) {
        auto split = [](const vk::Buffer& b) {
            const VkDeviceAddress a = b.deviceAddress();
            return glm::uvec2(uint32_t(a), uint32_t(a >> 32));
        };
#define VKP_ARRAY_ADDRESS(index, name, Record, access, member) \
    VKP_SCENE_ARRAY_IF_SPANS_##access(addresses.name = split(g.name);)
        VKP_SCENE_ARRAYS(VKP_ARRAY_ADDRESS)
#undef VKP_ARRAY_ADDRESS
    }
    g.addresses = vk::Buffer::fromSpan(context, std::span(&addresses, 1), "sceneAddresses");
    return g;
}

void releaseUploaded(SceneTables& t) {
    const auto release = [](auto& array) { std::decay_t<decltype(array)>().swap(array); };
    release(t.bvh.nodes);
    release(t.bvh.traversalNodes);
    release(t.bvh.primitives);
#define VKP_ARRAY_RELEASE(index, name, Record, access, member) \
    VKP_SCENE_ARRAY_IF_SPANS_##access(release(t.member);)
    VKP_SCENE_ARRAYS(VKP_ARRAY_RELEASE)
#undef VKP_ARRAY_RELEASE
}

std::string describeMemory(const GpuScene& g, const SceneTables& t) {
    std::string surface;
    if (t.surface.attributes != 0)
        surface = fmt::format(
            "; vertex attributes: {} triangles, {} vertices ({:.1f} KiB)",
            t.surface.triangleVertices.size(),
            std::max({t.surface.vertexNormals.size(), t.surface.vertexTexcoords.size(),
                      t.surface.vertexColors.size(), t.surface.vertexTangents.size()}),
            (g.triangleVertices.size() + g.vertexNormals.size() + g.vertexTexcoords.size() +
             g.vertexColors.size() + g.vertexTangents.size()) /
                1024.0);
    if (!t.textures.textures.empty())
        surface += fmt::format("; textures: {} ({} texels, {:.1f} MiB)", t.textures.textures.size(),
                               t.textures.texels.size(), g.texels.size() / (1024.0 * 1024.0));
    return fmt::format("scene: {:.1f} MiB on the device ({}{}), {}", g.bytes() / (1024.0 * 1024.0),
                       bvh::describeMemory(t.bvh), surface,
                       g.byAddress ? "read by buffer device address (larger than one binding)"
                                   : "bound as texel buffers");
}

}  // namespace vkpath::wavefront
