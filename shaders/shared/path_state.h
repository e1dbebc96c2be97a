// A path between two of its vertices, and its start at the camera: what the
// wavefront's per-path buffers hold (stages/lib/path_buffers.glsl) and what
// the loop of shared/integrator.h carries. Needs no scene, so stage
// "generate" and the loop share it.
#ifndef VKPATH_SHARED_PATH_STATE_H
#define VKPATH_SHARED_PATH_STATE_H

#include "shared/camera.h"
#include "shared/compat.h"
#include "shared/dimensions.h"
#include "shared/features.h"
#include "shared/ray.h"
#include "shared/rng.h"
#include "shared/scene_data.h"
#include "shared/spectral.h"

VKP_NAMESPACE_BEGIN

// The albedo and normal AOVs of a path (--aov albedo,normal; the denoiser's
// guides): what its first non-delta hit shows, following delta bounces
// (shared/integrator.h recordAov). A pixel's AOV is the mean over its
// samples (shared/wavefront.h FilmAovPixel).
struct PathAov {
    vec3 albedo;  // in [0, 1] (shared/bsdf.h materialAlbedo)
    vec3 normal;  // world space, unit (0 where the path left the scene)
    uint found;   // 1 once the values are final: a non-delta hit, or the path left the scene
};

// What a path carries from one vertex to the next: the wavefront's per-path
// buffers hold exactly this (rays, throughput, radiance, vertices; the AOVs
// only in renders that ask for them).
struct PathState {
    Ray ray;                // the next ray to trace
    vec3 throughput;        // product of BSDF weights (and roulette) so far
    float etaScale;         // product of eta'^2 over the refractions so far (Russian roulette)
    vec3 radiance;          // gathered so far
    vec3 previousPosition;  // world space: the last scattering point (the camera for the first ray)
    // Its geometric normal (shared/unit_vector.h), kept with the light tree
    // (SceneInfo::treeLights), else 0
    uint previousNormal;
    float bsdfPdf;       // density of the direction sampled there (MIS at the next hit)
    bool specular;       // the camera or a delta BSDF produced the ray (no MIS)
    bool afterNonDelta;  // a non-delta lobe scattered the path before (path regularisation applies)
    // The wavelength in nm the path follows since it met dispersive glass
    // (shared/spectral.h); 0 before. Kept only with VKP_FEATURE_DISPERSION.
    float wavelength;
    PathAov aov;  // read and written only with VKP_FEATURE_AOVS and SceneInfo::aovs
};

// What a path's rays were, for RenderResult's counters.
struct PathTally {
    uint closestRays;
    uint shadowRays;            // light samples with a non-zero contribution, traced
    uint rejectedLightSamples;  // light samples of density 0 (ShadowRequest::rejected)
};

// The key of path `sampleIndex` of `pixel`: every random number it draws.
// The odd stream's seed is the render's seed with these bits flipped.
#define VKP_ODD_STREAM_SEED 0x9e3779b9u

VKP_FN RngKey pathRngKey(VKP_IN(SceneInfo) info, uint pixel, uint sampleIndex) {
    // Two streams (SceneInfo::sampleStreams): index i is sample i / 2 of the
    // randomisation seeded by seed (i even) or by another seed (i odd).
    uint seed = info.seed;
    if (info.sampleStreams == 2u) {
        seed ^= (sampleIndex & 1u) * VKP_ODD_STREAM_SEED;
        sampleIndex >>= 1u;
    }
    return makeRngKey(pixel, sampleIndex, seed, featureSampler(info.samplerKind));
}

// SceneInfo::lightSamples, a constant when the kernel's features fix it
// (none, or exactly one).
VKP_FN uint featureLightSamples(uint lightSamples) {
    if (!hasFeature(VKP_FEATURE_LIGHT_SAMPLES)) return 0u;
    if (!hasFeature(VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES)) return 1u;
    return lightSamples;
}

// Stage "generate": the camera ray through a jittered point of `pixel` (box
// filter), throughput 1.
VKP_FN PathState startPath(VKP_IN(Camera) camera, uint pixel, RngKey key) {
    PathState path;
    uvec2 xy = uvec2(pixel % camera.width, pixel / camera.width);
    path.ray = generateCameraRay(camera, xy, rngUniform2(key, VKP_DIM_PIXEL_JITTER));
    path.throughput = vec3(1.0f);
    path.etaScale = 1.0f;
    path.radiance = vec3(0.0f);
    path.previousPosition = camera.origin;
    path.previousNormal = 0u;
    path.bsdfPdf = 0.0f;
    path.specular = true;
    path.afterNonDelta = false;
    path.wavelength = 0.0f;
    path.aov.albedo = vec3(0.0f);
    path.aov.normal = vec3(0.0f);
    path.aov.found = 0u;
    return path;
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_PATH_STATE_H
