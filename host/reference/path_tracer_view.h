// The kernels' path-tracing math on the CPU: the bodies of
// shaders/shared/path_tracer.h and integrator.h (the per-path loop) become the
// const member functions of PathTracerViewOf<Features>, which reads the scene
// tables (wavefront::SceneTables, what the GPU buffers hold) through
// std::span where the shade kernel reads its texel buffers
// (shaders/stages/lib/scene_access.glsl). Rays are traced through the
// eight-wide tree collapsed from the scene's BVH (host/bvh/wide_bvh.h), whose
// leaves are tested by shared/bvh_leaf.h included here, so with this view's
// alpha test (path_tracer.h bvhAlphaTest, which reads materials and
// textures): the hits the kernels' binary traversal finds, bit for bit. One
// object answers everything a path vertex asks:
//
//   shared::PathTracerView view(tables, info);
//   shared::Hit hit = view.bvhClosestHit(ray);
//   shared::ShadowRequest r = view.sampleDirectLight(material, surface, wo, guide, beta, key,
//   bounce, j);
//
// Features is the translation unit's shared::kernelFeatures (a static_assert
// says so): the general code everywhere, except in the CPU reference's
// profile translation units (shared/feature_profiles.h), which compile
// the shared code for a feature set as the GPU's specialised pipelines do.
// PathTracerView names the view of the translation unit's features.
//
// It lives in vkpath::shared because the included code names shared types and
// GLM functions unqualified, as GLSL does.
#pragma once

#include <span>

#include "bvh/wide_bvh.h"
#include "shared/alias.h"
#include "shared/alpha.h"
#include "shared/bsdf.h"
#include "shared/constants.h"
#include "shared/environment_sampling.h"
#include "shared/features.h"
#include "shared/light_tree.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/medium.h"
#include "shared/mesh_attributes.h"
#include "shared/microfacet_albedo.h"
#include "shared/path_state.h"
#include "shared/phase.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/scene_arrays.h"
#include "shared/scene_data.h"
#include "shared/texture.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::shared {

// The scene as the shared code's accessors read it, with the wide tree: what
// every feature set's view reads alike.
struct SceneTablesView {
    // `tables` must outlive the view; `info` is the render's SceneInfo
    // (wavefront::renderSceneInfo). Throws std::invalid_argument when the
    // tables' sizes disagree with each other or with `info`, the one thing
    // the GPU would read out of bounds without a word.
    SceneTablesView(const wavefront::SceneTables& tables, const SceneInfo& info);

    // The accessors shared/bvh_leaf.h and path_tracer.h read through.
    BvhPrimitive bvhPrimitive(uint index) const { return m_primitives[index]; }
    uvec4 bvhNodeTexel(uint texel) const { return m_nodes[texel]; }
    const SceneInfo& sceneInfo() const { return m_info; }
    Material sceneMaterial(uint index) const { return m_materials[index]; }
    Light sceneLight(uint index) const { return m_lights[index]; }
    AliasEntry sceneLightAlias(uint index) const { return m_lightAlias[index]; }
    uint scenePrimitiveLight(uint leafPrimitive) const {
        return m_primitiveLight.empty() ? VKP_NO_LIGHT : m_primitiveLight[leafPrimitive];
    }
    AliasEntry sceneEnvAlias(uint texel) const { return m_envAlias[texel]; }
    vec3 sceneEnvRadiance(uint texel) const { return vec3(m_envRadiance[texel]); }
    TriangleVertices sceneTriangleVertices(uint triangle) const {
        return m_triangleVertices[triangle];
    }
    vec3 sceneVertexNormal(uint vertex) const { return vec3(m_vertexNormals[vertex]); }
    vec4 sceneVertexTexcoords(uint vertex) const { return m_vertexTexcoords[vertex]; }
    vec4 sceneVertexColor(uint vertex) const { return m_vertexColors[vertex]; }
    vec4 sceneVertexTangent(uint vertex) const { return m_vertexTangents[vertex]; }
    TextureInfo sceneTexture(uint index) const { return m_textures[index]; }
    TextureSlot sceneTextureSlot(uint index) const { return m_textureSlots[index]; }
    vec4 sceneTexel(uint index) const {
        const uvec2 packed = m_texels[index];
        return vec4(unpackHalf2x16(packed.x), unpackHalf2x16(packed.y));
    }
    MaterialAlpha sceneMaterialAlpha(uint index) const { return m_materialAlpha[index]; }
    vec4 sceneGuideSphere(uint index) const { return m_guideSpheres[index]; }
    float sceneMicrofacetAlbedo(uint index) const { return m_microfacetAlbedo[index]; }
    LightTreeNode sceneLightTreeNode(uint index) const { return m_lightTree[index]; }
    uint sceneLightTreeTrail(uint light) const { return m_lightTreeTrail[light]; }
    Medium sceneMedium(uint index) const { return m_media[index]; }
    GridMedium sceneGridMedium() const { return m_gridMedium[0]; }
    float sceneGridDensity(uint index) const { return m_gridDensity[index]; }
    float sceneGridMajorant(uint index) const { return m_gridMajorant[index]; }

    const bvh::WideBvh& wideBvh() const { return m_wide; }

  private:
    std::span<const BvhPrimitive> m_primitives;  // leaf order
    std::span<const uvec4> m_nodes;              // the node texels and instance records
    bvh::WideBvh m_wide;
    SceneInfo m_info;
    // One per row of shaders/shared/scene_arrays.h: m_materials, m_lights, ...
#define VKP_ARRAY_SPAN(index, name, Record, access, member) std::span<const Record> m_##name;
    VKP_SCENE_ARRAYS(VKP_ARRAY_SPAN)
#undef VKP_ARRAY_SPAN
    std::span<const vec4> m_guideSpheres;
};

template <FeatureMask Features>
struct PathTracerViewOf : SceneTablesView {
    static_assert(
        Features == kernelFeatures,
        "a view is compiled with the shared code of its own features: define VKP_CPU_FEATURES "
        "before the first include (shared/feature_profiles.h)");
    static constexpr uint features = Features;

    using SceneTablesView::SceneTablesView;

    // What shared/integrator.h traces with: the wide tree, the hits of the
    // kernels' binary traversal.
    Hit bvhClosestHit(VKP_IN(Ray) ray, uint alphaKey) const {
        return bvh::traceWide(*this, wideBvh(), ray, false, alphaKey);
    }
    bool bvhOccluded(VKP_IN(Ray) ray, uint alphaKey) const {
        return bvh::traceWide(*this, wideBvh(), ray, true, alphaKey).primitive != VKP_NO_HIT;
    }
    Hit bvhClosestHit(VKP_IN(Ray) ray) const { return bvhClosestHit(ray, 0u); }
    bool bvhOccluded(VKP_IN(Ray) ray) const { return bvhOccluded(ray, 0u); }

    // The included functions become members: plain inline, also where the
    // free functions of a profile's translation unit are static.
#pragma push_macro("VKP_FN")
#undef VKP_FN
#define VKP_FN inline
// In the order each needs the ones before it:
// clang-format off
#include "shared/bvh_leaf.h"
#include "shared/path_tracer.h"
#include "shared/integrator.h"
// clang-format on
#pragma pop_macro("VKP_FN")
};

using PathTracerView = PathTracerViewOf<kernelFeatures>;

}  // namespace vkpath::shared
