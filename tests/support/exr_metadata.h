// The "vkpath:" attributes `vkpath render` writes into an EXR's header.
#pragma once

#include <map>
#include <string>

#include "image/image.h"
#include "input_error.h"

namespace vkpath::test {

// Every attribute whose name starts with "vkpath:", as strings; empty when
// the file cannot be opened.
inline std::map<std::string, std::string> vkpathMetadata(const std::string& path) {
    try {
        return image::readVkpathMetadata(path);
    } catch (const InputError&) {
        return {};
    }
}

}  // namespace vkpath::test
