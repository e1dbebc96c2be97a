// The vkpath command line. Exit codes: 0 success, 1 internal or Vulkan
// failure (or validation messages when validation is on), 2 bad input or flags.
#pragma once

namespace vkpath::app {

int runCli(int argc, char** argv);

}  // namespace vkpath::app
