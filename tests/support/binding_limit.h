// Sets VKPATH_MAX_BINDING_BYTES (vk::bufferLimits) for the life of the
// object, so a test can send small scenes down the by-address path.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>

namespace vkpath::test {

class BindingLimit {
  public:
    explicit BindingLimit(uint64_t bytes) {
        setenv("VKPATH_MAX_BINDING_BYTES", std::to_string(bytes).c_str(), 1);
    }
    ~BindingLimit() { unsetenv("VKPATH_MAX_BINDING_BYTES"); }
    BindingLimit(const BindingLimit&) = delete;
    BindingLimit& operator=(const BindingLimit&) = delete;
};

}  // namespace vkpath::test
