// Descriptor binding indices and push-constant blocks of the kernels, named
// once here and used by both the GLSL kernels and the host that binds them.
// Every kernel uses descriptor set 0 and `layout(local_size_x_id = 0)`, so the
// host picks its workgroup size through specialisation constant 0.
#ifndef VKPATH_SHARED_BINDINGS_H
#define VKPATH_SHARED_BINDINGS_H

#include "shared/compat.h"

// Specialisation constant ids shared by all kernels.
#define VKP_SPEC_WORKGROUP_SIZE 0

// ---- generate: camera rays for one sample of a range of pixels -------------
#define VKP_GENERATE_BINDING_CAMERA 0  // Camera (one element)
#define VKP_GENERATE_BINDING_RAYS 1    // Ray[count], written

VKP_NAMESPACE_BEGIN

struct GeneratePush {
    uint firstPixel;   // pixel index of invocation 0
    uint count;        // number of rays to generate
    uint sampleIndex;  // sample index within each pixel (RNG counter)
    uint seed;         // render seed (RNG counter)
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::GeneratePush) == 16);
#endif

#endif  // VKPATH_SHARED_BINDINGS_H
