// The scene as the integrators read it, besides the BVH (shared/bvh.h):
// materials, lights with the alias table that picks them by power, the
// environment and its sampling table, and the settings of a render.
#ifndef VKPATH_SHARED_SCENE_DATA_H
#define VKPATH_SHARED_SCENE_DATA_H

#include "shared/compat.h"
#include "shared/environment_sampling.h"

// SceneInfo::environmentLight and the per-primitive light index when there is none.
#define VKP_NO_LIGHT 0xffffffffu

VKP_NAMESPACE_BEGIN

// The most spheres diffuse samples are guided toward (SceneInfo::guideSphereCount).
#define VKP_MAX_GUIDE_SPHERES 8u

struct SceneInfo {
    EnvironmentInfo environment;  // width 0: constant `color` (when hasEnvironment)
    uint hasEnvironment;          // 0: rays that escape see black
    uint lightCount;              // entries in the light list and in its alias table's first part
    uint environmentLight;        // index of the environment in the light list, or VKP_NO_LIGHT
    uint lightSamples;            // light samples per non-specular vertex (-l)
    uint maxDepth;                // bounces, pbrt-v4's meaning: 0 = emitters seen directly only
    uint rouletteDepth;           // bounce from which Russian roulette may end paths
    uint seed;                    // the render's seed (RNG counter)
    uint width;                   // film size in pixels
    uint height;
    float clampRadiance;  // > 0: each path sample's largest component is clamped to this (biased)
    float fireflyThreshold;   // samples above this (largest component) are counted as fireflies
    uint samplerKind;         // VKP_SAMPLER_* (shared/rng.h): where the random numbers come from
    uint triangleAttributes;  // VKP_TRIANGLE_* bits some triangle has (shared/mesh_attributes.h):
                              // the per-triangle and per-vertex arrays exist only if non-zero
    uint alphaTested;  // 1: some triangle's material may leave holes (alphaMode MASK or BLEND) and
                       // the MaterialAlpha[] table exists (shared/alpha.h); 0: all is opaque
    float regularizeAlpha;  // > 0: path regularisation, the least GGX alpha of a lobe after the
                            // path's first non-delta scattering (shared/bsdf.h regularizedMaterial;
                            // biased)
    uint unsampledEmitters;  // 1: some emissive surface is no light (textured or with holes): only
                             // BSDF samples find it (shared/path_tracer.h lightSamplingAlone)
    uint guideSphereCount;   // spheres that diffuse samples are guided toward (shared/path_tracer.h
                             // sampleGuidedDiffuse); their (centre, radius) follow the SceneInfo in
                             // its buffer
    float guideFraction;     // the share of a guided vertex's samples drawn toward the spheres
    // 2: even and odd sample indices are two independent randomisations of
    // the sampler (shared/path_state.h pathRngKey), whose means' difference
    // measures a render's error where the sample variance cannot (Sobol'
    // points are not independent); 1: one (wavefront/sample_schedule.h).
    uint sampleStreams;
    // 1: the render keeps each path's albedo and normal AOVs (--aov albedo,normal;
    // shared/integrator.h recordAov, with VKP_FEATURE_AOVS); 0: no AOV code runs
    uint aovs;
    // 1: the microfacet lobes get their multiple scattering back
    // (shared/microfacet_albedo.h; with VKP_FEATURE_MICROFACET_COMPENSATION);
    // 0: single scattering, as Mitsuba 3 and pbrt-v4 (render --single-scattering)
    uint microfacetCompensation;
    // > 0: lights [0, treeLights) are chosen through the light tree
    // (shared/light_tree.h; with VKP_FEATURE_LIGHT_TREE), and the light alias
    // table's entries from lightCount on choose between the tree and each
    // light after it; 0: every light by the alias table over their power
    uint treeLights;
    // 1: the media array holds the fog and each material's inside
    // (shared/medium.h; with VKP_FEATURE_MEDIA), and each bounce draws its
    // free flight; 0: no medium anywhere
    uint media;
    // 1: the grid medium of render --volume (shared/medium.h GridMedium, with
    // VKP_FEATURE_GRID_MEDIUM) fills its box, besides the fog; 0: none
    uint gridMedium;
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::SceneInfo) == 128);
#endif

#endif  // VKPATH_SHARED_SCENE_DATA_H
