#include "scene/environment.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "input_error.h"

namespace vkpath::scene {
namespace {

// OpenEXR (3.1) trusts the size an attribute declares: a 2 KB file whose
// string attribute claims 1.7 GB makes it allocate and fill that much before
// the read fails (found by fuzz/environment_fuzz). So before OpenImageIO
// opens an OpenEXR file, each attribute of each header (file layout: magic,
// version, then per header name\0 type\0 size value ... \0) must fit in the
// file. Anything else malformed is left to OpenEXR to report.
void checkExrAttributeSizes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    auto u32 = [&](uint32_t& value) {
        unsigned char b[4];
        if (!in.read(reinterpret_cast<char*>(b), 4)) return false;
        value = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
        return true;
    };
    auto text = [&](std::string& value) {  // names and types have at most 255 characters
        value.clear();
        for (char c; in.get(c);) {
            if (c == '\0') return true;
            if (value.size() == 255) return false;
            value += c;
        }
        return false;
    };
    uint32_t magic = 0, version = 0;
    if (!u32(magic) || magic != 20000630 || !u32(version)) return;
    std::error_code ec;
    const uint64_t fileSize = std::filesystem::file_size(path, ec);
    if (ec) return;
    const bool multipart = (version & 0x1000) != 0;
    for (bool emptyHeader = false; !emptyHeader;) {
        emptyHeader = true;
        for (std::string name, type; text(name) && !name.empty();) {
            emptyHeader = false;
            uint32_t size = 0;
            if (!text(type) || !u32(size)) return;
            const uint64_t remaining = fileSize - uint64_t(in.tellg());
            if (size > remaining)
                throw InputError(fmt::format("{}: OpenEXR attribute '{}' claims {} bytes; the file "
                                             "has {} left",
                                             path.string(), name, int32_t(size), remaining));
            in.seekg(std::streamoff(size), std::ios::cur);
        }
        if (!multipart || !in) return;
    }
}

}  // namespace

image::Image loadEnvironmentMap(const std::filesystem::path& path, uint64_t maxPixels) {
    const std::string file = path.string();
    checkExrAttributeSizes(path);
    image::Image map = image::readImage(path, maxPixels);  // checks the size before reading pixels

    size_t negative = 0;
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x) {
            glm::vec3& texel = map.at(x, y);
            for (int c = 0; c < 3; ++c) {
                if (!std::isfinite(texel[c]))
                    throw InputError(fmt::format("{}: texel ({}, {}) is not finite ({}, {}, {})",
                                                 file, x, y, texel.x, texel.y, texel.z));
                if (texel[c] < 0.0f) {
                    ++negative;
                    texel[c] = 0.0f;
                }
            }
        }
    if (negative > 0)
        std::fprintf(stderr, "vkpath: warning: %s: %zu negative texel values clamped to 0\n",
                     file.c_str(), negative);
    if (uint64_t(map.width) != 2 * uint64_t(map.height))
        std::fprintf(stderr,
                     "vkpath: warning: %s: %ux%u is not 2:1; the map is stretched over the sphere "
                     "as it is\n",
                     file.c_str(), map.width, map.height);
    return map;
}

}  // namespace vkpath::scene
