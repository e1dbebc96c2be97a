// Sampling a discrete distribution in O(1) with an alias table (Walker 1977;
// Vose, IEEE TSE 17(9), 1991), built on the host in double precision
// (host/scene/alias_table.h). Used for environment-map texels and for
// choosing a light by power.
//
// A sample takes two 32-bit random words: the first picks a bucket
// uniformly, the second keeps the bucket's own element when it is below the
// bucket's threshold and takes the alias otherwise. Thresholds are 32-bit,
// so elements with tiny probabilities keep them (a float CDF loses whole
// ranges below one ulp of its total), and `probability` is computed from the
// quantised table itself: what the sampler draws is what the pdf reads.
//
// GLSL cannot pass buffers to functions, so the caller reads entries:
//   bucket = aliasBucket(bits0, count); element = aliasResolve(table[bucket], bucket, bits1);
//   p = table[element].probability;
#ifndef VKPATH_SHARED_ALIAS_H
#define VKPATH_SHARED_ALIAS_H

#include "shared/compat.h"

VKP_NAMESPACE_BEGIN

struct AliasEntry {
    uint threshold;     // the bucket keeps its own element when bits < threshold, else takes `alias`
    uint alias;         // element index
    float probability;  // this element's exact probability under the quantised table
    uint padding;       // 0: an entry is one 16-byte texel (stages/lib/scene_access.glsl)
};

// floor(bits * count / 2^32): uniform over [0, count) for count <= 2^32.
VKP_FN uint aliasBucket(uint bits, uint count) {
#ifdef __cplusplus
    return uint((uint64_t(bits) * uint64_t(count)) >> 32);
#else
    uint high;
    uint low;
    umulExtended(bits, count, high, low);
    return high;
#endif
}

VKP_FN uint aliasResolve(AliasEntry entry, uint bucket, uint bits) {
    return bits < entry.threshold ? bucket : entry.alias;
}

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::AliasEntry) == 16);
#endif

#endif  // VKPATH_SHARED_ALIAS_H
