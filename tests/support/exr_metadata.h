// The "vkpath:" attributes `vkpath render` writes into an EXR's header.
#pragma once

#include <OpenImageIO/imageio.h>

#include <map>
#include <string>

namespace vkpath::test {

// Every attribute whose name starts with "vkpath:", as strings; empty when
// the file cannot be opened.
inline std::map<std::string, std::string> vkpathMetadata(const std::string& path) {
    std::map<std::string, std::string> attributes;
    auto in = OIIO::ImageInput::open(path);
    if (!in) return attributes;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs) {
        const std::string name = p.name().string();
        if (name.rfind("vkpath:", 0) == 0) attributes[name] = p.get_string();
    }
    return attributes;
}

}  // namespace vkpath::test
