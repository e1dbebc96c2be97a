// The interface of tests/kernels/bsdf_dispatch.comp: one material sampled and
// evaluated through shared/bsdf.h's dispatch (sampleBsdf, evalBsdf, bsdfPdf)
// at a fixed wo, in world space. Results are microfacet_routines.h's records.
#ifndef VKPATH_TESTS_BSDF_DISPATCH_H
#define VKPATH_TESTS_BSDF_DISPATCH_H

#include "shared/compat.h"

VKP_NAMESPACE_BEGIN

struct BsdfDispatchPush {
    uint count;  // samples
    uint seed;
    vec3 wo;  // world space, unit
    vec3 ng;  // geometric normal, world space, unit
    vec3 ns;  // shading normal, oriented like ng
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::BsdfDispatchPush) == 44);  // the scalar layout's size
#endif

#endif
