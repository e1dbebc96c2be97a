// Textures as the kernels read them: one texel store for all images (RGBA as
// half floats, already decoded to linear values on the host: an image used
// both as sRGB colour and as linear data is stored once per decoding), a
// record per texture (where its texels start, its size, how it wraps and
// filters), and per textured material a row of slots, one per texture use,
// each with its texture coordinate set and KHR_texture_transform matrix.
//
// Coordinates follow glTF 2.0 (section 3.9.1 "Images" / "Samplers"): (0, 0)
// is the top-left corner of the image (the first texel row in memory), u to
// the right, v down; texel (i, j) covers [i, i + 1] / width x [j, j + 1] /
// height, so its centre is at ((i + 0.5) / width, (j + 0.5) / height).
// Bilinear filtering weights the four texels whose centres surround the
// point; nearest takes the texel the point lies in. Wrapping is applied to
// texel indices, as OpenGL's REPEAT, CLAMP_TO_EDGE and MIRRORED_REPEAT are.
//
// Like path_tracer.h the lookup reads through an accessor its includer
// defines: vec4 sceneTexel(uint index) (the store's entry, unpacked).
#ifndef VKPATH_SHARED_TEXTURE_H
#define VKPATH_SHARED_TEXTURE_H

#include "shared/compat.h"
#include "shared/records.h"

// TextureInfo::sampling: wrap mode of u in bits 0-1, of v in bits 2-3 (the
// numbers of scene::TextureWrap), nearest filtering in bit 4.
#define VKP_WRAP_REPEAT 0u
#define VKP_WRAP_CLAMP_TO_EDGE 1u
#define VKP_WRAP_MIRRORED_REPEAT 2u
#define VKP_TEXTURE_NEAREST 16u

// Material::textures and TextureSlot::texture where there is none.
#define VKP_NO_TEXTURE 0xffffffffu

// A textured material's slots, in this order from Material::textures on.
#define VKP_SLOT_BASE_COLOR 0u  // sRGB colour and linear alpha: multiplies the base colour
#define VKP_SLOT_EMISSIVE 1u    // sRGB colour: multiplies the emission
#define VKP_SLOT_METALLIC_ROUGHNESS \
    2u  // linear: G roughness, B metalness (glTF), multiplying the factors
#define VKP_SLOT_NORMAL \
    3u  // linear: tangent-space normal, (2 x - 1) scaled in x and y by the normal scale
#define VKP_SLOT_CLEARCOAT 4u             // linear: R multiplies the clear coat's weight
#define VKP_SLOT_CLEARCOAT_ROUGHNESS 5u   // linear: G multiplies the clear coat's roughness
#define VKP_SLOT_SHEEN_COLOR 6u           // sRGB colour: multiplies the sheen colour
#define VKP_SLOT_SHEEN_ROUGHNESS 7u       // linear: A multiplies the sheen roughness
#define VKP_SLOT_DIFFUSE_TRANSMISSION 8u  // linear: A multiplies the diffuse transmission's share
#define VKP_SLOT_DIFFUSE_TRANSMISSION_COLOR 9u  // sRGB colour: multiplies its colour
#define VKP_SLOT_IRIDESCENCE 10u                // linear: R multiplies the thin film's weight
#define VKP_SLOT_IRIDESCENCE_THICKNESS \
    11u  // linear: G picks the film's thickness between its minimum and maximum
#define VKP_SLOT_ANISOTROPY \
    12u  // linear: RG the direction in the tangent frame (2 x - 1), B multiplies the strength
#define VKP_SLOT_CLEARCOAT_NORMAL \
    13u  // linear: the clear coat's tangent-space normal, as VKP_SLOT_NORMAL
#define VKP_SLOTS_PER_MATERIAL 14u

VKP_NAMESPACE_BEGIN

// TextureInfo's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_TEXTURE_INFO_FIELDS(F)                                    \
    /* index of texel (0, 0) in the store; rows follow one another */ \
    F(uint, firstTexel, 0)                                            \
    F(uint, width, 1)                                                 \
    F(uint, height, 2)                                                \
    /* wrap modes and filter, see above */                            \
    F(uint, sampling, 3)
struct TextureInfo {
    VKP_TEXTURE_INFO_FIELDS(VKP_FIELD_DECLARE)
};

// One use of a texture by a material: uv' = (dot(transformU, (u, v, 1)),
// dot(transformV, (u, v, 1))), the KHR_texture_transform matrix T R S.
// TextureSlot's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_TEXTURE_SLOT_FIELDS(F)                                              \
    F(vec3, transformU, 0)                                                      \
    /* index into TextureInfo[], VKP_NO_TEXTURE: the slot is empty (value 1) */ \
    F(uint, texture, 3)                                                         \
    F(vec3, transformV, 4)                                                      \
    /* 0 or 1: TEXCOORD_0 or TEXCOORD_1 */                                      \
    F(uint, texCoord, 7)                                                        \
    /* VKP_SLOT_NORMAL: glTF's normalTexture.scale; 1 in the other slots */     \
    F(float, scale, 8)                                                          \
    /* 0: a slot is three 16-byte texels (stages/lib/scene_access.glsl) */      \
    F(uvec3, padding, 9)
struct TextureSlot {
    VKP_TEXTURE_SLOT_FIELDS(VKP_FIELD_DECLARE)
};

// Texel index `i` (any integer) wrapped into [0, n).
VKP_FN int wrapTexelIndex(int i, int n, uint mode) {
    if (mode == VKP_WRAP_CLAMP_TO_EDGE) return clamp(i, 0, n - 1);
    if (mode == VKP_WRAP_MIRRORED_REPEAT) {
        int period = 2 * n;
        int m = i % period;
        if (m < 0) m += period;
        return m < n ? m : period - 1 - m;
    }
    int m = i % n;
    return m < 0 ? m + n : m;
}

// floor(x) as an int, for x far outside any texture's range too: coordinates
// are clamped to +-2^30 first (no overflow; REPEAT at such a coordinate has
// lost its fraction to float rounding long before).
VKP_FN int floorToInt(float x) {
    return int(floor(clamp(x, -1073741824.0f, 1073741824.0f)));
}

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD TextureInfo
VKP_RECORD_CHECK(VKP_TEXTURE_INFO_FIELDS, 1)
#undef VKP_RECORD
#define VKP_RECORD TextureSlot
VKP_RECORD_CHECK(VKP_TEXTURE_SLOT_FIELDS, 3)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_TEXTURE_H
