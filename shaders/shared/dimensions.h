// The order in which one path consumes random numbers: each dimension index
// names one use, so CPU and GPU renderers draw the same number for the same
// decision. The bounces' dimensions follow (shared/path_tracer.h,
// bounceDimension).
#ifndef VKPATH_SHARED_DIMENSIONS_H
#define VKPATH_SHARED_DIMENSIONS_H

#define VKP_DIM_PIXEL_JITTER 0u  // 2 numbers: sub-pixel position

#endif  // VKPATH_SHARED_DIMENSIONS_H
