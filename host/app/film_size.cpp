#include "app/film_size.h"

#include <fmt/format.h>

#include <charconv>

#include "input_error.h"

namespace vkpath::app {

FilmSize parseFilmSize(const std::string& text) {
    const auto x = text.find('x');
    FilmSize size{0, 0};
    bool ok = x != std::string::npos;
    if (ok) {
        const char* begin = text.data();
        const char* end = begin + text.size();
        auto [p1, e1] = std::from_chars(begin, begin + x, size.width);
        auto [p2, e2] = std::from_chars(begin + x + 1, end, size.height);
        ok = e1 == std::errc() && p1 == begin + x && e2 == std::errc() && p2 == end;
    }
    constexpr uint32_t MAX_SIDE = 16384;
    if (!ok || size.width == 0 || size.height == 0 || size.width > MAX_SIDE ||
        size.height > MAX_SIDE)
        throw InputError(
            fmt::format("film size '{}' is not WxH with sides from 1 to {}", text, MAX_SIDE));
    return size;
}

}  // namespace vkpath::app
