// The path tracer's per-vertex math, shared by the wavefront stages and the
// CPU reference renderer: emission with its MIS weight, one light sample
// (next-event estimation), and the BSDF sample that continues the path with
// Russian roulette. Like shared/bvh_traverse.h it reads the scene through
// accessors its includer defines:
//
//   SceneInfo sceneInfo();
//   Material sceneMaterial(uint index);
//   Light sceneLight(uint index);
//   AliasEntry sceneLightAlias(uint index);
//   uint scenePrimitiveLight(uint leafPrimitive);   // VKP_NO_LIGHT if not emissive
//   AliasEntry sceneEnvAlias(uint texel);
//   vec3 sceneEnvRadiance(uint texel);              // linear RGB, before strength
//   BvhPrimitive bvhPrimitive(uint index);          // from the BVH
//   uvec4 bvhNodeTexel(uint texel);                 // the BVH's nodes and instance records
//   TriangleVertices sceneTriangleVertices(uint triangle);  // by BvhPrimitive::id
//   (shared/mesh_attributes.h) vec3 sceneVertexNormal(uint vertex); vec4 sceneVertexTexcoords(uint
//   vertex);         // (TEXCOORD_0, TEXCOORD_1) vec4 sceneVertexColor(uint vertex); vec4
//   sceneVertexTangent(uint vertex);           // unit xyz, w = +-1: B = w (N x T) TextureInfo
//   sceneTexture(uint index);           // shared/texture.h TextureSlot sceneTextureSlot(uint
//   index); vec4 sceneTexel(uint index);                    // linear RGBA MaterialAlpha
//   sceneMaterialAlpha(uint index);   // shared/alpha.h; read only when SceneInfo::alphaTested
//   float sceneMicrofacetAlbedo(uint index);  // shared/microfacet_albedo.h; read only when
//                                             // SceneInfo::microfacetCompensation
//   LightTreeNode sceneLightTreeNode(uint index);  // shared/light_tree.h; read only when
//   uint sceneLightTreeTrail(uint light);          // SceneInfo::treeLights > 0
//   Medium sceneMedium(uint index);  // shared/medium.h; read only with VKP_FEATURE_MEDIA
//   GridMedium sceneGridMedium();    // shared/medium.h; these three read only with
//   float sceneGridDensity(uint index);   // SceneInfo::gridMedium
//   float sceneGridMajorant(uint index);
//
// It defines the alpha test that shared/bvh_traverse.h asks (bvhAlphaTest).
//
// No include guard: include once per scope (C++: inside the reference
// renderer's scene view struct, so these become const member functions).
//
// Multiple importance sampling: light sampling (N = lightSamples samples per
// vertex) and BSDF sampling are combined with the power heuristic with
// sample counts (Veach's thesis, section 9.2): a light sample of density p_l
// (light choice times direction) is weighted (N p_l)^2 / ((N p_l)^2 + p_b^2)
// and divided by N; an emitter hit by the BSDF sample of density p_b gets
// p_b^2 / (p_b^2 + (N p_l)^2). Delta lights and delta BSDFs take weight 1.

#ifdef __cplusplus
#define VKP_SCENE_CONST const
#else
#define VKP_SCENE_CONST
#endif

// Random dimensions: after the pixel jitter, each bounce uses
// VKP_DIMS_PER_BOUNCE_BASE + VKP_DIMS_PER_LIGHT_SAMPLE * lightSamples numbers.
// Every 2-D quantity starts at an even dimension, the pairs that the Sobol'
// sampler stratifies together (shared/rng.h); roulette's single number is
// paired with the lobe choice of the materials that choose between lobes
// with a number of their own (sampleBsdf's uc) and with the component of a
// guided Lambertian vertex's mixture (sampleGuidedDiffuse), which no other
// material draws, so adding them changed no other material's numbers.
// With media, each bounce's segment draws its free flight from a pair after
// those four (shared/path/media.h crossMedium); without, the layout is as
// before media.
#define VKP_DIMS_PER_BOUNCE_BASE                                                       \
    (4u /* BSDF direction (2), Russian roulette (1), lobe or component choice (1) */ + \
     (mediaOn() ? 2u : 0u))
#define VKP_DIM_FREE_FLIGHT 4u        // the distance and the channel it is drawn for
#define VKP_DIMS_PER_LIGHT_SAMPLE 4u  // environment texel (2 words), light choice and position (2)

// SceneInfo::lightSamples, a constant when the kernel's features fix it.
VKP_FN uint lightSampleCount() VKP_SCENE_CONST {
    return featureLightSamples(sceneInfo().lightSamples);
}

// Whether the scene has media (SceneInfo::media), a constant false in
// kernels without them.
VKP_FN bool mediaOn() VKP_SCENE_CONST {
    return hasFeature(VKP_FEATURE_MEDIA) && sceneInfo().media != 0u;
}

VKP_FN uint bounceDimension(uint bounce) VKP_SCENE_CONST {
    return 2u +
           bounce * (VKP_DIMS_PER_BOUNCE_BASE + VKP_DIMS_PER_LIGHT_SAMPLE * lightSampleCount());
}

// The per-vertex math, one file per concern, in the order each needs the
// ones before it (so clang-format leaves the order alone).
// clang-format off
#include "shared/path/environment.h"
#include "shared/path/instances.h"
#include "shared/path/textures.h"
#include "shared/path/shading_normals.h"
#include "shared/path/alpha_test.h"
#include "shared/path/absorption.h"
#include "shared/path/energy_compensation.h"
#include "shared/path/sphere_guiding.h"
#include "shared/path/media.h"
#include "shared/path/light_choice.h"
#include "shared/path/emission.h"
#include "shared/path/next_event.h"
#include "shared/path/continuation.h"
// clang-format on
