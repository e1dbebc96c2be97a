// Linear RGB float images and their files: EXR (float32, with metadata) and
// PNG previews (sRGB-encoded, with an exposure in stops).
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/ext/vector_uint4_sized.hpp>
#include <glm/vec3.hpp>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace vkpath::image {

struct Image {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<glm::vec3> pixels;  // row-major from the top-left, linear RGB

    Image() = default;
    Image(uint32_t w, uint32_t h) : width(w), height(h), pixels(size_t(w) * h, glm::vec3(0)) {}
    glm::vec3& at(uint32_t x, uint32_t y) { return pixels[size_t(y) * width + x]; }
    const glm::vec3& at(uint32_t x, uint32_t y) const { return pixels[size_t(y) * width + x]; }
};

// Attributes written into the EXR header as strings, e.g. {"vkpath:spp", "64"}.
using Metadata = std::vector<std::pair<std::string, std::string>>;

// Each writer writes to a temporary file beside `path` and renames it into
// place, so a failure never leaves a partial file. Throws std::runtime_error
// naming the file on failure.
void writeExr(const std::filesystem::path& path, const Image& image, const Metadata& metadata = {});
void writePng(const std::filesystem::path& path, const Image& image, float exposureStops = 0.0f);

// Reads the first three channels of any image OpenImageIO reads (EXR, HDR,
// PNG...), as linear floats; a one-channel image is replicated to grey.
// Throws vkpath::InputError naming the file when it cannot be read or is
// larger than maxPixels.
Image readImage(const std::filesystem::path& path, uint64_t maxPixels = uint64_t(1) << 28);

// An image as its file stores it: RGBA, 16-bit normalised (8-bit values
// widened exactly, v x 257), rows from the top, no colour decoding.
struct Rgba16Image {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<glm::u16vec4> texels;
};

// Decodes an image file held in memory (PNG, JPEG, and whatever else
// OpenImageIO reads from memory); `format` is the file extension that names
// its reader ("png", "jpg"). Grey becomes RGB, a missing alpha 1. Throws
// vkpath::InputError (without a file name: the caller knows where the bytes
// came from) when it cannot be decoded or has more than maxPixels pixels.
Rgba16Image decodeImage(std::span<const uint8_t> bytes, const std::string& format,
                        uint64_t maxPixels);

// The attributes of an image's header whose names start with "vkpath:" (what
// writeExr wrote), as strings. Throws vkpath::InputError naming the file when
// it cannot be opened.
std::map<std::string, std::string> readVkpathMetadata(const std::filesystem::path& path);

// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
float linearToSrgb(float linear);

}  // namespace vkpath::image
