#include "app/validators.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "app/film_size.h"
#include "input_error.h"

namespace vkpath::app {
namespace {

// The text as a T, rounded as the option's own conversion rounds it; nullopt
// for text that is not a number.
template <typename T>
std::optional<T> real(const std::string& text) {
    T value = 0;
    const char* begin = text.data() + (!text.empty() && text[0] == '+');
    const char* end = text.data() + text.size();
    const auto [stop, error] = std::from_chars(begin, end, value);
    // Out of T's range: std::from_chars leaves `value` alone; it is infinite.
    if (error == std::errc::result_out_of_range && stop == end)
        return std::numeric_limits<T>::infinity();
    if (error != std::errc() || stop != end || text.empty()) return std::nullopt;
    return value;
}

// A validator of a real number that `accepts`: `what` ends the message
// "'TEXT' is not WHAT", `description` follows the type in --help.
template <typename T>
CLI::Validator realValidator(std::string what, std::string description,
                             std::function<bool(T)> accepts) {
    return CLI::Validator(
        [what, accepts](std::string& text) {
            const std::optional<T> value = real<T>(text);
            return value && accepts(*value) ? std::string()
                                            : fmt::format("'{}' is not {}", text, what);
        },
        std::move(description));
}

}  // namespace

template <typename T>
CLI::Validator realIn(double low, double high, bool highOpen) {
    const std::string interval = fmt::format("[{}, {}{}", low, high, highOpen ? ")" : "]");
    return realValidator<T>(
        "a number in " + interval, "in " + interval,
        [low, high, highOpen](T v) { return v >= low && (highOpen ? v < high : v <= high); });
}

template <typename T>
CLI::Validator realAtLeast(double low) {
    return realValidator<T>(fmt::format("a finite number >= {}", low), fmt::format(">= {}", low),
                            [low](T v) { return std::isfinite(v) && v >= low; });
}

template <typename T>
CLI::Validator realAbove(double low, bool finite) {
    return realValidator<T>(
        fmt::format("a {}number > {}", finite ? "finite " : "", low), fmt::format("> {}", low),
        [low, finite](T v) { return v > low && (!finite || std::isfinite(v)); });
}

template <typename T>
CLI::Validator finiteReal() {
    return realValidator<T>("a finite number", "finite", [](T v) { return std::isfinite(v); });
}

template CLI::Validator realIn<float>(double, double, bool);
template CLI::Validator realIn<double>(double, double, bool);
template CLI::Validator realAtLeast<float>(double);
template CLI::Validator realAtLeast<double>(double);
template CLI::Validator realAbove<float>(double, bool);
template CLI::Validator realAbove<double>(double, bool);
template CLI::Validator finiteReal<float>();
template CLI::Validator finiteReal<double>();

CLI::Validator parsedBy(const std::string& description, void (*parse)(const std::string&)) {
    return CLI::Validator(
        [parse](std::string& text) {
            try {
                parse(text);
                return std::string();
            } catch (const InputError& e) {
                return std::string(e.what());
            }
        },
        description);
}

CLI::Validator filmSizeValidator() {
    return parsedBy("WxH", [](const std::string& text) { parseFilmSize(text); });
}

}  // namespace vkpath::app
