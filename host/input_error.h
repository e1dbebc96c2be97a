// Bad user input (a scene, an image, a flag) is an expected failure: the
// command line prints the message as one line and exits with code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace vkpath {

class InputError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace vkpath
