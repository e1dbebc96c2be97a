// Device timestamps around recorded work: each named interval is written as a
// pair of queries, read back after the submission completes, and reported in
// milliseconds of device time.
#pragma once

#include <vulkan/vulkan.h>

#include <string>
#include <vector>

namespace vkpath::vk {

class Context;

struct TimedInterval {
    std::string name;
    double milliseconds = 0;
};

class TimestampPool {
  public:
    // Room for `capacity` intervals per submission.
    TimestampPool(Context& context, uint32_t capacity);
    ~TimestampPool();
    TimestampPool(const TimestampPool&) = delete;
    TimestampPool& operator=(const TimestampPool&) = delete;

    // Whether the device can time work at all; when not, begin/end record nothing.
    bool enabled() const { return m_pool != VK_NULL_HANDLE; }

    // Records a reset of all queries; call once per command buffer before begin().
    void reset(VkCommandBuffer cmd);
    // Opens the interval `name`; returns its index.
    uint32_t begin(VkCommandBuffer cmd, std::string name);
    void end(VkCommandBuffer cmd, uint32_t interval);
    // After the command buffer has completed: every interval since reset().
    std::vector<TimedInterval> results() const;

  private:
    Context& m_context;
    VkQueryPool m_pool = VK_NULL_HANDLE;
    uint32_t m_capacity = 0;
    std::vector<std::string> m_names;
};

}  // namespace vkpath::vk
