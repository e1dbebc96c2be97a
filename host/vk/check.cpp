#include "vk/check.h"

#include <fmt/format.h>

namespace vkpath::vk {

const char* resultName(VkResult result) {
    switch (result) {
#define VKP_RESULT_CASE(name) \
    case name:                \
        return #name;
        VKP_RESULT_CASE(VK_SUCCESS)
        VKP_RESULT_CASE(VK_NOT_READY)
        VKP_RESULT_CASE(VK_TIMEOUT)
        VKP_RESULT_CASE(VK_EVENT_SET)
        VKP_RESULT_CASE(VK_EVENT_RESET)
        VKP_RESULT_CASE(VK_INCOMPLETE)
        VKP_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        VKP_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        VKP_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
        VKP_RESULT_CASE(VK_ERROR_DEVICE_LOST)
        VKP_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        VKP_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        VKP_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        VKP_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        VKP_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        VKP_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        VKP_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        VKP_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
        VKP_RESULT_CASE(VK_ERROR_UNKNOWN)
        VKP_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        VKP_RESULT_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        VKP_RESULT_CASE(VK_ERROR_FRAGMENTATION)
        VKP_RESULT_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        VKP_RESULT_CASE(VK_PIPELINE_COMPILE_REQUIRED)
        VKP_RESULT_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
#undef VKP_RESULT_CASE
        default:
            return "VK_RESULT_UNKNOWN";
    }
}

void throwVulkanError(VkResult result, const char* call, const char* file, int line) {
    throw VulkanError(result,
                      fmt::format("{} failed with {} ({}) at {}:{}", call, resultName(result),
                                  static_cast<int>(result), file, line));
}

}  // namespace vkpath::vk
