// Every Vulkan call goes through VK_CHECK: a failure throws VulkanError naming
// the call, the VkResult and the source location.
#pragma once

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace vkpath::vk {

// The enumerator's name, e.g. "VK_ERROR_DEVICE_LOST".
const char* resultName(VkResult result);

class VulkanError : public std::runtime_error {
  public:
    VulkanError(VkResult result, const std::string& message)
        : std::runtime_error(message), m_result(result) {}
    VkResult result() const { return m_result; }

  private:
    VkResult m_result;
};

[[noreturn]] void throwVulkanError(VkResult result, const char* call, const char* file, int line);

}  // namespace vkpath::vk

#define VK_CHECK(call)                                                                 \
    do {                                                                               \
        const VkResult vkCheckResult_ = (call);                                        \
        if (vkCheckResult_ != VK_SUCCESS)                                              \
            ::vkpath::vk::throwVulkanError(vkCheckResult_, #call, __FILE__, __LINE__); \
    } while (false)
