// Runs the built vkpath executable as a user would and captures what it says.
#pragma once

#include <string>

namespace vkpath::test {

struct CommandResult {
    int exitCode = -1;
    std::string out;  // stdout
    std::string err;  // stderr
};

// `args` is appended to the vkpath path as-is (shell syntax).
CommandResult runVkpath(const std::string& args);

// The number of lines in `text` (a last line without '\n' counts).
int lineCount(const std::string& text);

}  // namespace vkpath::test
