// The order in which one path consumes random numbers: each dimension index
// names one use, so CPU and GPU renderers draw the same number for the same
// decision. The bounces' dimensions follow (shared/path_tracer.h,
// bounceDimension).
#ifndef VKPATH_SHARED_DIMENSIONS_H
#define VKPATH_SHARED_DIMENSIONS_H

#define VKP_DIM_PIXEL_JITTER 0u  // 2 numbers: sub-pixel position

// The version of what a path does with its numbers: their order (here and
// in shared/path_tracer.h) and the estimator they feed. A render's settings
// carry it (host/app/render_options.cpp renderIdentity), so a checkpoint or a
// part for `vkpath merge` from a build of another version is refused, not
// mixed with samples of another sequence. Raise it with every change that
// alters the image of a given seed. 2: the light chosen from the point's
// pair, and light sampling alone at a Lambertian last vertex (2026-12-04).
// 3: the concentric disk's cosine and sine by polynomial (sampling.h). 4: a
// triangle light's normal and area from the host (lights.h). 5: diffuse
// samples guided toward smooth specular spheres (path_tracer.h). 6: lights
// chosen through the light tree (path/light_choice.h), and point and spot
// lights' range (lights.h). 7: scattering inside glass
// (KHR_materials_volume_scatter, path/media.h), which files that have it
// rendered without before. 8: anisotropy (KHR_materials_anisotropy) and
// dispersion (KHR_materials_dispersion, shared/spectral.h), which files that
// have them rendered without before, emission dimmed by a clear coat, and
// a clear coat's own normal map.
#define VKP_ESTIMATOR_VERSION 8u

#endif  // VKPATH_SHARED_DIMENSIONS_H
