// Images for textures, the same for every importer: the format an image
// file's bytes are in, the limits on one image and on a scene's texels, and
// decoding (OpenImageIO, image::decodeImage) into Scene::images, with the
// warning or the error each failure gets.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/import_warnings.h"
#include "scene/scene.h"

namespace vkpath::scene {

// Pixels of one image, and texels of all a scene's textures together: 2^28
// texels are 2 GiB in the device's texel store (8 bytes each), the budget.
constexpr uint64_t MAX_IMAGE_PIXELS = uint64_t(1) << 26;
constexpr uint64_t MAX_SCENE_TEXELS = uint64_t(1) << 28;

// The format an image's bytes are in, as a file extension OpenImageIO knows
// ("png", "jpg", "webp", "ktx2", "tga"): from their magic number, else the
// MIME type, else the URI's extension; "" when none says.
std::string imageFormat(const std::vector<uint8_t>& bytes, const std::string& mimeType,
                        const std::string& uri);

// Decodes an image file's `bytes` (`format` as imageFormat names it) and
// appends it to scene.images as `name`; returns its index. Bytes that cannot
// be decoded (none, an unknown format, a broken file, more than
// MAX_IMAGE_PIXELS) are a warning, counted per image, and -1: the textures
// that use the image are left out. An image that takes the scene past
// MAX_SCENE_TEXELS is an InputError naming `file`, the scene's file.
int32_t addTextureImage(Scene& scene, const std::vector<uint8_t>& bytes, const std::string& format,
                        const std::string& name, const std::string& file, ImportWarnings& warnings);

}  // namespace vkpath::scene
