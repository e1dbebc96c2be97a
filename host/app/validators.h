// The checks of the command line's values, as CLI11 validators: a value that
// fails one ends the parse with one line, "vkpath: --flag: what is wrong",
// and exit code 2 (app/cli.cpp). Whole numbers use CLI::Range and files
// CLI::ExistingFile; these cover what CLI11 2.1 does not say clearly: real
// numbers (its Range lets NaN through and prints its bounds as six-decimal
// doubles), and the formats WxH, FIRST:COUNT and lists, each checked by the
// parser the command then uses, so the two cannot disagree.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace vkpath::app {

// A real number (of type T: float or double, whose range it must fit) that
// is finite and lies in [low, high], or in [low, high) where `highOpen`.
template <typename T>
CLI::Validator realIn(double low, double high, bool highOpen = false);

// A real number of type T that is finite and >= low.
template <typename T>
CLI::Validator realAtLeast(double low);

// A real number of type T greater than `low`; +inf is accepted unless `finite`.
template <typename T>
CLI::Validator realAbove(double low, bool finite = true);

// Any finite real number of type T.
template <typename T>
CLI::Validator finiteReal();

// The value as `parse` reads it: its InputError's message becomes the error.
// `description` names the format in --help.
CLI::Validator parsedBy(const std::string& description, void (*parse)(const std::string&));

// "WxH" as app::parseFilmSize reads it.
CLI::Validator filmSizeValidator();

}  // namespace vkpath::app
