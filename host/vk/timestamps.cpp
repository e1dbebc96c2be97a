#include "vk/timestamps.h"

#include <stdexcept>

#include "vk/check.h"
#include "vk/context.h"

namespace vkpath::vk {

TimestampPool::TimestampPool(Context& context, uint32_t capacity)
    : m_context(context), m_capacity(capacity) {
    if (!context.info().timestamps || capacity == 0) return;
    VkQueryPoolCreateInfo create{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    create.queryType = VK_QUERY_TYPE_TIMESTAMP;
    create.queryCount = 2 * capacity;
    VK_CHECK(vkCreateQueryPool(context.device(), &create, nullptr, &m_pool));
}

TimestampPool::~TimestampPool() {
    if (m_pool) vkDestroyQueryPool(m_context.device(), m_pool, nullptr);
}

void TimestampPool::reset(VkCommandBuffer cmd) {
    m_names.clear();
    if (m_pool) vkCmdResetQueryPool(cmd, m_pool, 0, 2 * m_capacity);
}

uint32_t TimestampPool::begin(VkCommandBuffer cmd, std::string name) {
    if (m_names.size() >= m_capacity) throw std::length_error("timestamp pool is full");
    const auto interval = static_cast<uint32_t>(m_names.size());
    m_names.push_back(std::move(name));
    if (m_pool) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m_pool, 2 * interval);
    return interval;
}

void TimestampPool::end(VkCommandBuffer cmd, uint32_t interval) {
    if (m_pool)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m_pool, 2 * interval + 1);
}

std::vector<TimedInterval> TimestampPool::results() const {
    std::vector<TimedInterval> intervals;
    if (m_names.empty()) return intervals;
    std::vector<uint64_t> ticks(2 * m_names.size(), 0);
    if (m_pool) {
        VK_CHECK(vkGetQueryPoolResults(
            m_context.device(), m_pool, 0, static_cast<uint32_t>(ticks.size()),
            ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    }
    const double msPerTick = m_context.info().timestampPeriodNs * 1e-6;
    for (size_t i = 0; i < m_names.size(); ++i) {
        const uint64_t elapsed =
            ticks[2 * i + 1] >= ticks[2 * i] ? ticks[2 * i + 1] - ticks[2 * i] : 0;
        intervals.push_back({m_names[i], static_cast<double>(elapsed) * msPerTick});
    }
    return intervals;
}

}  // namespace vkpath::vk
