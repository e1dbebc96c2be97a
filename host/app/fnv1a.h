// FNV-1a, 64 bits: the fingerprint of a render's scene files
// (app::renderIdentity) and of a checkpoint's contents (app/checkpoint.h).
// Not a security hash.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace vkpath::app {

inline constexpr uint64_t FNV1A_OFFSET = 0xcbf29ce484222325ull;

// `hash` continued over `bytes` (start from FNV1A_OFFSET).
inline uint64_t fnv1a(std::span<const std::byte> bytes, uint64_t hash = FNV1A_OFFSET) {
    for (std::byte b : bytes) hash = (hash ^ uint8_t(b)) * 0x100000001b3ull;
    return hash;
}

}  // namespace vkpath::app
