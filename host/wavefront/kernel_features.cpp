#include "wavefront/kernel_features.h"

#include <fmt/format.h>

#include <array>
#include <utility>

#include "scene/scene.h"
#include "shared/alpha.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/mesh_attributes.h"
#include "shared/rng.h"
#include "shared/texture.h"

namespace vkpath::wavefront {
namespace {

// Each feature's name in the logs; a material kind's is its registry label
// (shaders/shared/material_kinds.h).
constexpr std::array<std::pair<uint64_t, const char*>, VKP_FEATURE_COUNT> FEATURE_NAMES = {{
    {VKP_FEATURE_TRIANGLES, "triangles"},
    {VKP_FEATURE_SPHERES, "spheres"},
#define VKP_KIND_FEATURE_NAME(id, NAME, Type, key, label, feature, flags, regularized) \
    {feature, label},
    VKP_MATERIAL_KINDS(VKP_KIND_FEATURE_NAME)
#undef VKP_KIND_FEATURE_NAME
        {VKP_FEATURE_EMISSIVE_SURFACES, "emissive-surfaces"},
    {VKP_FEATURE_POINT_LIGHTS, "point-lights"},
    {VKP_FEATURE_SPOT_LIGHTS, "spot-lights"},
    {VKP_FEATURE_DIRECTIONAL_LIGHTS, "directional-lights"},
    {VKP_FEATURE_ENVIRONMENT_COLOR, "environment-color"},
    {VKP_FEATURE_ENVIRONMENT_MAP, "environment-map"},
    {VKP_FEATURE_SAMPLER_INDEPENDENT, "independent-sampler"},
    {VKP_FEATURE_SAMPLER_SOBOL, "sobol-sampler"},
    {VKP_FEATURE_LIGHT_SAMPLES, "light-samples"},
    {VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES, "multiple-light-samples"},
    {VKP_FEATURE_ROULETTE, "roulette"},
    {VKP_FEATURE_SHADING_NORMALS, "shading-normals"},
    {VKP_FEATURE_TEXTURES, "textures"},
    {VKP_FEATURE_VERTEX_COLORS, "vertex-colors"},
    {VKP_FEATURE_NORMAL_MAPS, "normal-maps"},
    {VKP_FEATURE_ALPHA, "alpha"},
    {VKP_FEATURE_REGULARIZE, "regularize"},
    {VKP_FEATURE_ABSORPTION, "absorption"},
    {VKP_FEATURE_DEEP_BVH, "deep-bvh"},
    {VKP_FEATURE_SPHERE_GUIDING, "sphere-guiding"},
    {VKP_FEATURE_AOVS, "aovs"},
    {VKP_FEATURE_INSTANCES, "instances"},
    {VKP_FEATURE_MICROFACET_COMPENSATION, "microfacet-compensation"},
    {VKP_FEATURE_LIGHT_TREE, "light-tree"},
    {VKP_FEATURE_LIGHT_RANGE, "light-range"},
    {VKP_FEATURE_MEDIA, "media"},
    {VKP_FEATURE_GRID_MEDIUM, "grid-medium"},
    {VKP_FEATURE_CLEARCOAT, "clearcoat"},
    {VKP_FEATURE_SHEEN, "sheen"},
    {VKP_FEATURE_THIN_WALLED, "thin-walled"},
    {VKP_FEATURE_DIFFUSE_TRANSMISSION, "diffuse-transmission"},
    {VKP_FEATURE_IRIDESCENCE, "iridescence"},
    {VKP_FEATURE_ANISOTROPY, "anisotropy"},
    {VKP_FEATURE_DISPERSION, "dispersion"},
}};

// The name of feature bit `bit`; every bit has one (a static_assert below).
constexpr const char* featureName(uint64_t bit) {
    for (const auto& [feature, name] : FEATURE_NAMES)
        if (feature == bit) return name;
    return nullptr;
}

constexpr bool namesEveryBit() {
    for (uint32_t i = 0; i < VKP_FEATURE_COUNT; ++i)
        if (featureName(VKP_FEATURE_BIT(i)) == nullptr) return false;
    return true;
}
static_assert(namesEveryBit(), "a VKP_FEATURE_* bit without a name");

}  // namespace

uint64_t sceneFeatures(const SceneTables& t) {
    uint64_t f = 0;
    for (size_t i = 0; i < t.materialPrimitives.size(); ++i) {
        const uint8_t worn = t.materialPrimitives[i];
        if (worn == 0) continue;
        const bool onTriangles = (worn & MATERIAL_ON_TRIANGLES) != 0;
        if (onTriangles) f |= VKP_FEATURE_TRIANGLES;
        if (worn & MATERIAL_ON_SPHERES) f |= VKP_FEATURE_SPHERES;
        const shared::Material& m = t.materials.at(i);
        f |= shared::materialFeature(m.kind);
        if (m.emission != glm::vec3(0.0f)) f |= VKP_FEATURE_EMISSIVE_SURFACES;
        if (m.attenuation != glm::vec3(0.0f)) f |= VKP_FEATURE_ABSORPTION;
        if (m.clearcoat > 0.0f) f |= VKP_FEATURE_CLEARCOAT;
        if (m.sheenColor != glm::vec3(0.0f)) f |= VKP_FEATURE_SHEEN;
        if (m.flags & VKP_MATERIAL_THIN_WALLED) f |= VKP_FEATURE_THIN_WALLED;
        if (m.diffuseTransmission > 0.0f) f |= VKP_FEATURE_DIFFUSE_TRANSMISSION;
        if (m.iridescence > 0.0f) f |= VKP_FEATURE_IRIDESCENCE;
        if (m.anisotropy > 0.0f) f |= VKP_FEATURE_ANISOTROPY;
        if (m.dispersion > 0.0f) f |= VKP_FEATURE_DISPERSION;
        if (m.textures != VKP_NO_TEXTURE && onTriangles) f |= VKP_FEATURE_TEXTURES;
        if (!t.materialAlpha.empty() && t.materialAlpha[i].mode != VKP_ALPHA_OPAQUE && onTriangles)
            f |= VKP_FEATURE_ALPHA;
    }
    // Delta lights by their type's bit; area lights come with their
    // primitives above, the environment below.
    for (const shared::Light& light : t.lights) {
        if (shared::lightTypeFlags(light.type) & VKP_LIGHT_IS_DELTA)
            f |= shared::lightTypeFeature(light.type);
        if ((light.type == VKP_LIGHT_POINT || light.type == VKP_LIGHT_SPOT) && light.radius > 0.0f)
            f |= VKP_FEATURE_LIGHT_RANGE;
    }
    f |= bvh::traversalFeatures(t.bvh);
    if (t.info.media != 0) f |= VKP_FEATURE_MEDIA;
    if (t.info.gridMedium != 0) f |= VKP_FEATURE_MEDIA | VKP_FEATURE_GRID_MEDIUM;
    if (t.info.triangleAttributes & VKP_TRIANGLE_SHADING_NORMALS) f |= VKP_FEATURE_SHADING_NORMALS;
    if (t.info.triangleAttributes & VKP_TRIANGLE_COLORS) f |= VKP_FEATURE_VERTEX_COLORS;
    if (t.info.triangleAttributes & VKP_TRIANGLE_TANGENTS) f |= VKP_FEATURE_NORMAL_MAPS;
    // The environment is seen by escaping rays whether or not it is bright
    // enough to be in the light list.
    if (t.info.hasEnvironment != 0)
        f |= t.info.environment.width != 0 ? VKP_FEATURE_ENVIRONMENT_MAP
                                           : VKP_FEATURE_ENVIRONMENT_COLOR;
    return f;
}

uint64_t renderFeatures(const SceneTables& tables, const shared::SceneInfo& info) {
    uint64_t f = sceneFeatures(tables);
    f |= info.samplerKind == VKP_SAMPLER_SOBOL ? VKP_FEATURE_SAMPLER_SOBOL
                                               : VKP_FEATURE_SAMPLER_INDEPENDENT;
    if (info.lightSamples > 0) f |= VKP_FEATURE_LIGHT_SAMPLES;
    if (info.lightSamples > 1) f |= VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES;
    // continuePath runs at bounces < maxDepth and applies roulette from
    // bounce + 1 >= rouletteDepth on.
    if (info.rouletteDepth <= info.maxDepth) f |= VKP_FEATURE_ROULETTE;
    // Guiding happens at Lambertian vertices that scatter (bounces < maxDepth).
    if (info.guideSphereCount > 0 && (f & VKP_FEATURE_DIFFUSE) && info.maxDepth > 0)
        f |= VKP_FEATURE_SPHERE_GUIDING;
    // Path regularisation (shared/bsdf.h regularizedMaterial) roughens the
    // delta and near-delta lobes: the mirror becomes a GGX conductor and the
    // smooth glass a rough one, so their kernels must hold those kinds too.
    // A kind's registry row names the kind it becomes; the kinds it changes
    // (or roughens: the microfacet kinds) make the feature.
    if (info.aovs != 0) f |= VKP_FEATURE_AOVS;
    if (info.regularizeAlpha > 0.0f) {
        uint64_t regularized = 0, roughened = 0;
        for (const scene::MaterialKindInfo& kind : scene::MATERIAL_KINDS) {
            if (!(f & kind.feature)) continue;
            regularized |= scene::materialKindInfo(kind.regularized).feature;
            if (kind.regularized != kind.kind || (kind.flags & VKP_KIND_MICROFACET))
                roughened |= kind.feature;
        }
        if (roughened != 0) f |= VKP_FEATURE_REGULARIZE | regularized;
    }
    // (set only for a scene with a rough GGX lobe: renderSceneInfo)
    if (info.microfacetCompensation != 0) f |= VKP_FEATURE_MICROFACET_COMPENSATION;
    if (info.treeLights != 0) f |= VKP_FEATURE_LIGHT_TREE;
    return f;
}

uint32_t shadowRaysPerVertex(uint64_t features, uint32_t lightSamples) {
    // shared/bsdf.h hasNonDeltaLobe: the kinds flagged VKP_KIND_NON_DELTA
    // (a microfacet kind only unless smooth: a set bit means "may occur").
    // (or a scattering event in a medium).
    const bool traces = (features & VKP_FEATURE_LIGHT_SAMPLES) != 0 &&
                        (features & (VKP_FEATURES_NON_DELTA | VKP_FEATURE_MEDIA)) != 0;
    return traces ? lightSamples : 0;
}

const char* featureProfile(uint64_t features) {
#define VKP_PROFILE_KEY(NAME, key, label) \
    if ((features & ~uint64_t(VKP_FEATURE_PROFILE_##NAME)) == 0) return #key;
    VKP_FEATURE_PROFILES(VKP_PROFILE_KEY)
#undef VKP_PROFILE_KEY
    return nullptr;
}

std::string profiledKernel(std::string_view name, uint64_t features) {
    const char* profile = featureProfile(features);
    return profile ? fmt::format("{}_{}", name, profile) : std::string(name);
}

std::string describeFeatures(uint64_t features) {
    if (features == VKP_FEATURES_ALL) return "general";
    std::string text;
    for (uint32_t i = 0; i < VKP_FEATURE_COUNT; ++i) {  // in the order of the bits
        if (!(features & VKP_FEATURE_BIT(i))) continue;
        if (!text.empty()) text += ' ';
        text += featureName(VKP_FEATURE_BIT(i));
    }
    return text.empty() ? "(none)" : text;
}

std::array<vk::SpecializationConstant, 2> featureConstants(uint64_t features) {
    return {{{VKP_SPEC_FEATURES, uint32_t(features)},
             {VKP_SPEC_FEATURES_HIGH, uint32_t(features >> 32)}}};
}

uint64_t specializedFeatures(std::span<const vk::SpecializationConstant> constants) {
    uint64_t low = uint32_t(VKP_FEATURES_ALL), high = uint32_t(VKP_FEATURES_ALL);
    for (const vk::SpecializationConstant& c : constants) {
        if (c.id == VKP_SPEC_FEATURES) low = c.value;
        if (c.id == VKP_SPEC_FEATURES_HIGH) high = c.value;
    }
    return high << 32 | low;
}

}  // namespace vkpath::wavefront
