// A byte count as people read it in messages: B, KiB, MiB or GiB.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <string>

namespace vkpath {

inline std::string formatBytes(uint64_t bytes) {
    if (bytes < 1024) return fmt::format("{} B", bytes);
    if (bytes < 1024 * 1024) return fmt::format("{:.1f} KiB", double(bytes) / 1024.0);
    if (bytes < 1024ull * 1024 * 1024)
        return fmt::format("{:.1f} MiB", double(bytes) / (1024.0 * 1024.0));
    return fmt::format("{:.1f} GiB", double(bytes) / (1024.0 * 1024.0 * 1024.0));
}

}  // namespace vkpath
