// Records declared by their fields. A record that the kernels read from a
// texel buffer (stages/lib/scene_access.glsl, shared/bvh_buffers.h) lists its
// fields once, with the 32-bit word each starts at:
//
//   #define VKP_LIGHT_FIELDS(F) F(vec3, p0, 0) F(uint, type, 3) ...
//   struct Light { VKP_LIGHT_FIELDS(VKP_FIELD_DECLARE) };
//
// and from that list come the struct, its C++ layout check
// (VKP_RECORD_CHECK: every field at 4 x its word, the size whole texels) and
// its decoding from 16-byte texels (VKP_RECORD_DECODE, GLSL). Fields are
// 32-bit scalars or vectors of them (uint, float, uvec2, uvec3, vec3), laid
// out as the `scalar` block layout and C++ both lay them out.
#ifndef VKPATH_SHARED_RECORDS_H
#define VKPATH_SHARED_RECORDS_H

#define VKP_FIELD_DECLARE(T, name, word) T name;

#ifdef __cplusplus
#include <cstddef>

// Inside VKP_RECORD_CHECK: the record the field belongs to.
#define VKP_FIELD_CHECK(T, name, word)                                       \
    static_assert(offsetof(vkpath::shared::VKP_RECORD, name) == 4u * (word), \
                  "a field's word in its list is not where C++ lays it out");
// Checks the struct `Record` against its field list `FIELDS` and its size of
// `texels` 16-byte texels. Use at file scope after the struct:
//   #define VKP_RECORD Light
//   VKP_RECORD_CHECK(VKP_LIGHT_FIELDS, 5)
//   #undef VKP_RECORD
#define VKP_RECORD_CHECK(FIELDS, texels) \
    FIELDS(VKP_FIELD_CHECK)              \
    static_assert(sizeof(vkpath::shared::VKP_RECORD) == 16u * (texels), "whole texels");
#else
// Word `word` of the texels t[] (uvec4 each, read in order).
#define VKP_TEXEL_WORD(t, word) t[(word) / 4][(word) % 4]
#define VKP_DECODE_uint(t, w) VKP_TEXEL_WORD(t, w)
#define VKP_DECODE_float(t, w) uintBitsToFloat(VKP_TEXEL_WORD(t, w))
#define VKP_DECODE_uvec2(t, w) uvec2(VKP_TEXEL_WORD(t, w), VKP_TEXEL_WORD(t, (w) + 1))
#define VKP_DECODE_uvec3(t, w) \
    uvec3(VKP_TEXEL_WORD(t, w), VKP_TEXEL_WORD(t, (w) + 1), VKP_TEXEL_WORD(t, (w) + 2))
#define VKP_DECODE_vec3(t, w) uintBitsToFloat(VKP_DECODE_uvec3(t, w))
// Inside VKP_RECORD_DECODE: the record `r` and the texels `t` it is read from.
#define VKP_FIELD_DECODE(T, name, word) r.name = VKP_DECODE_##T(t, word);
// The statements that fill `r` from `t`, for a field list.
#define VKP_RECORD_DECODE(FIELDS) FIELDS(VKP_FIELD_DECODE)
#endif

#endif  // VKPATH_SHARED_RECORDS_H
