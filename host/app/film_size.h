#pragma once

#include <cstdint>
#include <string>

namespace vkpath::app {

struct FilmSize {
    uint32_t width;
    uint32_t height;
};

// "WxH" with 1 <= W, H <= 16384; throws InputError otherwise.
FilmSize parseFilmSize(const std::string& text);

}  // namespace vkpath::app
