// The scene's textures flattened for the integrators (shared/texture.h): the
// texel store (RGBA half floats, decoded to linear values here, once per
// image and decoding), a record per (texture, decoding) and the slots of each
// textured material. Empty when no material has a texture.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "scene/scene.h"
#include "shared/texture.h"

namespace vkpath::wavefront {

struct TextureTables {
    std::vector<shared::TextureInfo> textures;
    std::vector<shared::TextureSlot> slots;  // VKP_SLOTS_PER_MATERIAL per textured material
    std::vector<glm::uvec2> texels;          // packHalf2x16(r, g), packHalf2x16(b, a)
    // Per scene material: its first slot (shared::Material::textures), or VKP_NO_TEXTURE.
    std::vector<uint32_t> materialSlots;
};

// Whether `material` reads a texture (and so texture coordinates).
bool usesTextures(const scene::Material& material);

// The sRGB transfer function's inverse (IEC 61966-2-1): encoded value in
// [0, 1] to linear.
double srgbToLinear(double encoded);

// Throws InputError when a texture or an image index is out of range or the
// store would pass 2^32 texels.
TextureTables buildTextureTables(const scene::Scene& scene);

}  // namespace vkpath::wavefront
