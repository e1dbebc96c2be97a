// Base64 (RFC 4648, with padding) for the data: URIs of glTF files that tests
// and the fuzzers' seed corpus write; the loader decodes them with tinygltf.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vkpath::test {

inline std::string base64(const std::vector<uint8_t>& data) {
    static const char* TABLE = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < data.size(); i += 3) {
        const uint32_t n = uint32_t(data[i]) << 16 |
                           (i + 1 < data.size() ? uint32_t(data[i + 1]) << 8 : 0) |
                           (i + 2 < data.size() ? uint32_t(data[i + 2]) : 0);
        out += TABLE[(n >> 18) & 63];
        out += TABLE[(n >> 12) & 63];
        out += i + 1 < data.size() ? TABLE[(n >> 6) & 63] : '=';
        out += i + 2 < data.size() ? TABLE[n & 63] : '=';
    }
    return out;
}

}  // namespace vkpath::test
