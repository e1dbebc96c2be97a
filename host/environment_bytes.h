// A byte count from an environment variable that lowers a limit for tests or
// a shared machine (VKPATH_MAX_BINDING_BYTES, VKPATH_HOST_MEMORY_BYTES).
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <cstdlib>
#include <optional>

#include "input_error.h"

namespace vkpath {

// The variable's value, or nullopt where it is unset or empty; throws
// InputError, one line, when it is not a positive whole number.
inline std::optional<uint64_t> environmentBytes(const char* variable) {
    const char* text = std::getenv(variable);
    if (!text || !*text) return std::nullopt;
    char* end = nullptr;
    const unsigned long long value = std::strtoull(text, &end, 10);
    if (*end != '\0' || value == 0)
        throw InputError(fmt::format("{}: '{}' is not a positive number of bytes", variable, text));
    return value;
}

}  // namespace vkpath
