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
//
// Or from one word, keeping what is left of it (aliasSampleReusing): the
// bucket is the high word of bits * count and the low word, uniform within
// the bucket, picks the element and is then rescaled to a number in [0, 1)
// that is uniform and independent of the choice (when the part it fell in
// holds enough words to give it resolution). One number then chooses a
// light and places the point on it, and a stratified set of numbers stays
// stratified over each element's share (sample reuse: Mitsuba 3's
// Scene::sample_emitter returns its sample rescaled so, for the emitter's
// own sampling).
#ifndef VKPATH_SHARED_ALIAS_H
#define VKPATH_SHARED_ALIAS_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/records.h"

VKP_NAMESPACE_BEGIN

// AliasEntry's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_ALIAS_ENTRY_FIELDS(F)                                                    \
    /* the bucket keeps its own element when bits < threshold, else takes `alias` */ \
    F(uint, threshold, 0)                                                            \
    /* element index */                                                              \
    F(uint, alias, 1)                                                                \
    /* this element's exact probability under the quantised table */                 \
    F(float, probability, 2)                                                         \
    /* 0: an entry is one 16-byte texel (stages/lib/scene_access.glsl) */            \
    F(uint, padding, 3)
struct AliasEntry {
    VKP_ALIAS_ENTRY_FIELDS(VKP_FIELD_DECLARE)
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

// bits * count mod 2^32: where `bits` lies within its bucket (aliasBucket),
// uniform over the 2^32 words when `bits` is uniform.
VKP_FN uint aliasBucketFraction(uint bits, uint count) {
    return bits * count;
}

// The fewest words a part of a bucket must hold for the rescaled fraction to
// serve as a number in [0, 1): below it (an element of tiny probability, or
// its sliver of a bucket) the caller draws the number afresh.
#define VKP_ALIAS_REUSE_MIN_WORDS 65536.0f

struct AliasChoice {
    uint element;
    float u;        // in [0, 1): the word's fraction within the element's part of the bucket
    bool reusable;  // the part held at least VKP_ALIAS_REUSE_MIN_WORDS words (else u has fewer
                    // values)
};

// The element of `bucket` (whose entry is `entry`) that the fraction
// `fraction` (aliasBucketFraction) picks, and that fraction rescaled from the
// part it fell in, [0, threshold) or [threshold, 2^32), to [0, 1).
VKP_FN AliasChoice aliasSampleReusing(AliasEntry entry, uint bucket, uint fraction) {
    AliasChoice choice;
    bool kept = fraction < entry.threshold;
    choice.element = kept ? bucket : entry.alias;
    float offset = float(fraction - (kept ? 0u : entry.threshold));
    float width = kept ? float(entry.threshold) : 4294967296.0f - float(entry.threshold);
    // (float rounding may bring an offset just below the width up to it)
    choice.u = min(offset / width, VKP_ONE_MINUS_EPSILON);
    choice.reusable = width >= VKP_ALIAS_REUSE_MIN_WORDS;
    return choice;
}

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD AliasEntry
VKP_RECORD_CHECK(VKP_ALIAS_ENTRY_FIELDS, 1)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_ALIAS_H
