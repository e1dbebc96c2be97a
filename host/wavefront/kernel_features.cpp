#include "wavefront/kernel_features.h"

#include <array>
#include <utility>

#include "shared/alpha.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/mesh_attributes.h"
#include "shared/rng.h"
#include "shared/texture.h"

namespace vkpath::wavefront {
namespace {

constexpr std::array<std::pair<uint32_t, const char*>, VKP_FEATURE_COUNT> FEATURE_NAMES = {{
    {VKP_FEATURE_TRIANGLES, "triangles"},
    {VKP_FEATURE_SPHERES, "spheres"},
    {VKP_FEATURE_DIFFUSE, "diffuse"},
    {VKP_FEATURE_MIRROR, "mirror"},
    {VKP_FEATURE_GLASS, "glass"},
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
    {VKP_FEATURE_CONDUCTOR, "conductor"},
    {VKP_FEATURE_ROUGH_GLASS, "rough-glass"},
    {VKP_FEATURE_METALLIC_ROUGHNESS, "metallic-roughness"},
    {VKP_FEATURE_ALPHA, "alpha"},
    {VKP_FEATURE_REGULARIZE, "regularize"},
    {VKP_FEATURE_ABSORPTION, "absorption"},
    {VKP_FEATURE_DEEP_BVH, "deep-bvh"},
    {VKP_FEATURE_SPHERE_GUIDING, "sphere-guiding"},
}};

}  // namespace

uint32_t sceneFeatures(const SceneTables& t) {
    uint32_t f = 0;
    for (const shared::BvhPrimitive& p : t.bvh.primitives) {
        f |= p.kind == VKP_PRIMITIVE_SPHERE ? VKP_FEATURE_SPHERES : VKP_FEATURE_TRIANGLES;
        const shared::Material& m = t.materials.at(p.material);
        f |= shared::materialFeature(m.kind);
        if (m.emission != glm::vec3(0.0f)) f |= VKP_FEATURE_EMISSIVE_SURFACES;
        if (m.attenuation != glm::vec3(0.0f)) f |= VKP_FEATURE_ABSORPTION;
        if (m.textures != VKP_NO_TEXTURE && p.kind == VKP_PRIMITIVE_TRIANGLE) f |= VKP_FEATURE_TEXTURES;
        if (!t.materialAlpha.empty() && t.materialAlpha[p.material].mode != VKP_ALPHA_OPAQUE &&
            p.kind == VKP_PRIMITIVE_TRIANGLE)
            f |= VKP_FEATURE_ALPHA;
    }
    for (const shared::Light& light : t.lights) {
        if (light.type == VKP_LIGHT_POINT) f |= VKP_FEATURE_POINT_LIGHTS;
        if (light.type == VKP_LIGHT_SPOT) f |= VKP_FEATURE_SPOT_LIGHTS;
        if (light.type == VKP_LIGHT_DIRECTIONAL) f |= VKP_FEATURE_DIRECTIONAL_LIGHTS;
    }
    f |= bvh::traversalFeatures(t.bvh);
    if (t.info.triangleAttributes & VKP_TRIANGLE_SHADING_NORMALS) f |= VKP_FEATURE_SHADING_NORMALS;
    if (t.info.triangleAttributes & VKP_TRIANGLE_COLORS) f |= VKP_FEATURE_VERTEX_COLORS;
    if (t.info.triangleAttributes & VKP_TRIANGLE_TANGENTS) f |= VKP_FEATURE_NORMAL_MAPS;
    // The environment is seen by escaping rays whether or not it is bright
    // enough to be in the light list.
    if (t.info.hasEnvironment != 0)
        f |= t.info.environment.width != 0 ? VKP_FEATURE_ENVIRONMENT_MAP : VKP_FEATURE_ENVIRONMENT_COLOR;
    return f;
}

uint32_t renderFeatures(const SceneTables& tables, const shared::SceneInfo& info) {
    uint32_t f = sceneFeatures(tables);
    f |= info.samplerKind == VKP_SAMPLER_SOBOL ? VKP_FEATURE_SAMPLER_SOBOL : VKP_FEATURE_SAMPLER_INDEPENDENT;
    if (info.lightSamples > 0) f |= VKP_FEATURE_LIGHT_SAMPLES;
    if (info.lightSamples > 1) f |= VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES;
    // continuePath runs at bounces < maxDepth and applies roulette from
    // bounce + 1 >= rouletteDepth on.
    if (info.rouletteDepth <= info.maxDepth) f |= VKP_FEATURE_ROULETTE;
    // Guiding happens at Lambertian vertices that scatter (bounces < maxDepth).
    if (info.guideSphereCount > 0 && (f & VKP_FEATURE_DIFFUSE) && info.maxDepth > 0) f |= VKP_FEATURE_SPHERE_GUIDING;
    // Path regularisation (shared/bsdf.h regularizedMaterial) roughens the
    // delta and near-delta lobes: the mirror becomes a GGX conductor and the
    // smooth glass a rough one, so their kernels must hold those kinds too.
    const uint32_t roughenable = VKP_FEATURE_MIRROR | VKP_FEATURE_GLASS | VKP_FEATURES_MICROFACET;
    if (info.regularizeAlpha > 0.0f && (f & roughenable) != 0) {
        f |= VKP_FEATURE_REGULARIZE;
        if (f & VKP_FEATURE_MIRROR) f |= VKP_FEATURE_CONDUCTOR;
        if (f & VKP_FEATURE_GLASS) f |= VKP_FEATURE_ROUGH_GLASS;
    }
    return f;
}

uint32_t shadowRaysPerVertex(uint32_t features, uint32_t lightSamples) {
    // shared/bsdf.h hasNonDeltaLobe: Lambertian and the microfacet kinds
    // (unless smooth: a set bit means "may occur") have one.
    const bool traces = (features & VKP_FEATURE_LIGHT_SAMPLES) != 0 &&
                        (features & (VKP_FEATURE_DIFFUSE | VKP_FEATURES_MICROFACET)) != 0;
    return traces ? lightSamples : 0;
}

std::string describeFeatures(uint32_t features) {
    if (features == VKP_FEATURES_ALL) return "general";
    std::string text;
    for (const auto& [bit, name] : FEATURE_NAMES) {
        if (!(features & bit)) continue;
        if (!text.empty()) text += ' ';
        text += name;
    }
    return text.empty() ? "(none)" : text;
}

}  // namespace vkpath::wavefront
