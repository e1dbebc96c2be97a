// The GPU integrator's buffers: path state as structure-of-arrays over the
// paths of one wave, two alternating ray queues and a shadow queue with
// their counters (stages/lib/queues.glsl), the indirect-dispatch arguments,
// and the film. Binding indices are shared by all stage kernels and the
// megakernel; each declares only what it uses, and the host binds what it
// declares (host/wavefront/renderer.cpp).
#ifndef VKPATH_SHARED_WAVEFRONT_H
#define VKPATH_SHARED_WAVEFRONT_H

#include "shared/compat.h"

// ---- bindings (descriptor set 0) ----------------------------------------------
#define VKP_WF_SCENE_INFO 0          // SceneInfo
#define VKP_WF_BVH_NODES 1           // BvhNode[]
#define VKP_WF_BVH_PRIMITIVES 2      // BvhPrimitive[]
#define VKP_WF_MATERIALS 3           // Material[]
#define VKP_WF_LIGHTS 4              // Light[]
#define VKP_WF_LIGHT_ALIAS 5         // AliasEntry[lightCount (+ lights outside the tree + 1)]
#define VKP_WF_PRIMITIVE_LIGHT 6     // uint[primitives]: light index of an emissive leaf primitive
#define VKP_WF_ENV_ALIAS 7           // AliasEntry[texels]
#define VKP_WF_ENV_RADIANCE 8        // vec3[texels]
#define VKP_WF_CAMERA 9              // Camera
#define VKP_WF_RAYS 10               // Ray[W]: each path's current ray
#define VKP_WF_HITS 11               // Hit[W]
#define VKP_WF_THROUGHPUT 12         // vec3[W]
#define VKP_WF_RADIANCE 13           // vec3[W]: radiance gathered by the path so far
#define VKP_WF_VERTEX 14             // PathVertex[W]
#define VKP_WF_QUEUES 15             // uint[3 W]: ray queue 0, ray queue 1, shadow queue
#define VKP_WF_COUNTERS 16           // QueueCounters
#define VKP_WF_SHADOW_RAYS 17        // Ray[W lightSamples]
#define VKP_WF_SHADOW_RADIANCE 18    // vec3[W lightSamples]: contribution if unoccluded
#define VKP_WF_FILM 19               // FilmPixel[width height]
#define VKP_WF_SCENE_ADDRESSES 20    // SceneAddresses (read when the scene is read by address)
#define VKP_WF_TRIANGLE_VERTICES 21  // TriangleVertices[triangles] (shared/mesh_attributes.h)
#define VKP_WF_VERTEX_NORMALS 22     // vec3[vertices]: world-space shading normals
#define VKP_WF_VERTEX_TEXCOORDS 23   // vec4[vertices]: TEXCOORD_0 (xy), TEXCOORD_1 (zw)
#define VKP_WF_VERTEX_COLORS 24      // vec4[vertices]: COLOR_0, linear RGBA
#define VKP_WF_TEXTURES 25           // TextureInfo[] (shared/texture.h)
#define VKP_WF_TEXTURE_SLOTS 26      // TextureSlot[]
#define VKP_WF_TEXELS 27             // uvec2[]: RGBA texels, two packHalf2x16 words each
#define VKP_WF_VERTEX_TANGENTS \
    28  // vec4[vertices]: world-space unit tangent (xyz), bitangent sign (w)
#define VKP_WF_MATERIAL_ALPHA \
    29  // MaterialAlpha[materials] (shared/alpha.h), when SceneInfo::alphaTested
#define VKP_WF_PIXEL_LIST \
    30  // uvec2[entries]: an adaptive pass's pixels (ascending) and each one's first sample index
#define VKP_WF_FILM_ODD 31  // FilmStreamPixel[width height]: the odd stream's sums (two streams)
#define VKP_WF_PATH_AOV 32  // PathAov[W]: each path's AOVs (SceneInfo::aovs)
#define VKP_WF_FILM_AOV 33  // FilmAovPixel[width height]: the AOVs' sums (SceneInfo::aovs)
#define VKP_WF_MICROFACET_ALBEDO \
    34                        // float[]: the albedo tables of shared/microfacet_albedo.h
                              // (SceneInfo::microfacetCompensation)
#define VKP_WF_LIGHT_TREE 35  // LightTreeNode[] (shared/light_tree.h), when SceneInfo::treeLights
#define VKP_WF_LIGHT_TREE_TRAIL \
    36  // uint[lightCount]: each light's path from the light tree's root, when
        // SceneInfo::treeLights
#define VKP_WF_MEDIA \
    37  // Medium[1 + materials] (shared/medium.h): the fog and each material's inside, with media
#define VKP_WF_GRID_MEDIUM 38   // GridMedium[1] (shared/medium.h), with SceneInfo::gridMedium
#define VKP_WF_GRID_DENSITY 39  // float[voxels]: the grid medium's densities
#define VKP_WF_GRID_MAJORANT \
    40  // float[cells]: the grid medium's majorant per cell of GridMedium::majorantCell^3 voxels
#define VKP_WF_PATH_WAVELENGTH \
    41  // float[W]: each path's wavelength (PathState::wavelength), with dispersion
// The first binding after the stages' own: kernels that bind the scene as the
// stages do put their own buffers from here (python/kernels/routines.h).
#define VKP_WF_FIRST_FREE_BINDING 42

VKP_NAMESPACE_BEGIN

// What shading at the next hit needs from the previous vertex.
// PathState's fields besides the ray, throughput and radiance, packed
// exactly: etaScale is positive, so its sign bit carries `specular`.
struct PathVertex {
    vec3 position;  // world space: the last scattering point (the camera for the first ray)
    float bsdfPdf;  // density of the direction sampled there (>= 0), its sign bit set when a
                    // non-delta lobe scattered the path before (PathState::afterNonDelta)
    float specularEtaScale;  // PathState::etaScale, negated when the ray is specular (the camera or
                             // a delta BSDF produced it: no MIS)
    uint normal;             // PathState::previousNormal
};

// Counters of the queues and the indirect-dispatch arguments computed from them.
struct QueueCounters {
    uint rayCount0;        // entries in ray queue 0 (even bounces)
    uint rayCount1;        // entries in ray queue 1 (odd bounces)
    uint shadowCount;      // entries in the shadow queue
    uint nonFinite;        // path samples dropped because their radiance was NaN or infinite
    uint fireflies;        // path samples above SceneInfo::fireflyThreshold (before any clamping)
    uvec3 rayDispatch;     // VkDispatchIndirectCommand for intersect and shade
    uvec3 shadowDispatch;  // VkDispatchIndirectCommand for shadow
    uint shadowRayCount;  // shadow rays shade asked for in this bounce (non-zero contributions), or
                          // the megakernel traced in this wave
    uint closestRayCount;  // closest-hit rays the megakernel traced in this wave
    // Rays traced over the whole render, as 64-bit (low, high) pairs summed by
    // queue_dispatch: closest-hit rays (intersect) and shadow rays (shadow).
    uvec2 closestRays;
    uvec2 shadowRays;
    uint rejectedLightSamples;  // light samples of density 0 from their vertex
                                // (ShadowRequest::rejected)
};

// Per-pixel sums over all samples so far, compensated (Kahan) so that 10^5
// and more samples keep every bit that matters: plain float sums stall once
// the sum reaches 2^24 times the addend.
struct FilmPixel {
    vec3 sum;
    vec3 sumCompensation;
    vec3 sumSquares;  // for the variance AOV
    vec3 sumSquaresCompensation;
};

// With two sample streams (SceneInfo::sampleStreams), the sum of each
// pixel's odd-indexed samples beside FilmPixel's sum of all of them.
struct FilmStreamPixel {
    vec3 sum;
    vec3 sumCompensation;
};

// With the AOVs (SceneInfo::aovs), each pixel's sums of its paths' PathAov
// values in sample order (plain float sums: an AOV is a guide, whose mean
// needs no more than float's 24 bits).
struct FilmAovPixel {
    vec3 albedo;
    vec3 normal;
    uint samples;  // the samples added (this render's, not a resumed state's)
};

// A wave is `pathCount` consecutive paths in (sample index, pixel) order,
// starting at pixel firstPixel of sample firstSample: path slot s is pixel
// (firstPixel + s) % pixels of sample firstSample + (firstPixel + s) / pixels
// (wavePathOf). Pixel and sample index stay separate 32-bit numbers, so a
// render may have any number of samples of any number of pixels.
// In an adaptive pass (pixelListLength > 0) the same order runs over the
// entries of the pixel list (VKP_WF_PIXEL_LIST) instead of the film's pixels,
// and the "sample index" is the round, added to the entry's first sample
// (stages/lib/common.glsl wavePath).
struct WavePush {
    uint firstSample;  // sample index (or round) of the wave's first path
    uint firstPixel;   // its pixel (or list entry), < width x height (or pixelListLength)
    uint pathCount;    // paths in this wave
    uint bounce;       // the bounce the stage works on
    uint mode;         // queue_dispatch: what to prepare (VKP_PREPARE_*)
    // accumulate: the first pixel of the film window bound. A film larger
    // than one storage-buffer binding (maxStorageBufferRange; 128 MiB on
    // lavapipe, 2.8 M pixels) or one dispatch (65535 workgroups) is kept in
    // windows, one buffer and one dispatch each.
    uint filmFirstPixel;
    uint pixelListLength;  // entries of the pass's pixel list; 0: the film's pixels in order
    // accumulate in an adaptive pass: the first list entry in the film window bound.
    uint listFirstEntry;
};

// (pixel, sample index) of path slot `slot` of the wave.
VKP_FN uvec2 wavePathOf(WavePush wave, uint slot, uint pixels) {
    uint linear = wave.firstPixel + slot;  // < pixels + pathCount: no overflow
    return uvec2(linear % pixels, wave.firstSample + linear / pixels);
}

#define VKP_PREPARE_RAYS \
    0u  // rayDispatch from the current ray queue; clear the next and the shadow queue
#define VKP_PREPARE_SHADOWS 1u  // shadowDispatch from the shadow queue
#define VKP_TALLY_RAYS 2u       // the megakernel's per-wave ray counts into the 64-bit totals

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::PathVertex) == 24);
static_assert(sizeof(vkpath::shared::QueueCounters) == 72);
static_assert(sizeof(vkpath::shared::FilmPixel) == 48);
static_assert(sizeof(vkpath::shared::FilmStreamPixel) == 24);
static_assert(sizeof(vkpath::shared::FilmAovPixel) == 28);
static_assert(sizeof(vkpath::shared::WavePush) == 32);
#endif

#endif  // VKPATH_SHARED_WAVEFRONT_H
