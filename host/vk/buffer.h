// Storage buffers in device-local memory, filled and read back through
// host-visible staging buffers.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstring>
#include <span>
#include <vector>

namespace vkpath::vk {

class Context;

enum class MemoryKind {
    DeviceLocal,  // where kernels read and write; reached through staging copies
    Staging,      // host-visible and coherent, for transfers
};

class Buffer {
  public:
    Buffer() = default;
    // A buffer of `size` bytes (at least 4) usable as a storage buffer, a copy
    // source and destination, and an indirect-dispatch argument buffer.
    Buffer(Context& context, VkDeviceSize size, MemoryKind kind = MemoryKind::DeviceLocal,
           const char* debugName = nullptr);
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    // A device-local buffer holding a copy of `data`.
    template <typename T, size_t Extent>
    static Buffer fromSpan(Context& context, std::span<T, Extent> data, const char* debugName = nullptr) {
        Buffer buffer(context, data.size_bytes(), MemoryKind::DeviceLocal, debugName);
        buffer.upload(std::as_bytes(data));
        return buffer;
    }

    VkBuffer handle() const { return m_buffer; }
    VkDeviceSize size() const { return m_size; }
    explicit operator bool() const { return m_buffer != VK_NULL_HANDLE; }

    // Copies bytes in at `offset` (staging copy and wait).
    void upload(std::span<const std::byte> bytes, VkDeviceSize offset = 0);
    // Copies `bytes.size()` bytes out from `offset` (staging copy and wait).
    void download(std::span<std::byte> bytes, VkDeviceSize offset = 0) const;
    // Sets every byte to zero on the device.
    void clear();

    template <typename T>
    std::vector<T> download() const {
        std::vector<T> values(m_size / sizeof(T));
        download(std::as_writable_bytes(std::span(values)));
        return values;
    }

  private:
    void release();
    void* mapped() const { return m_mapped; }

    Context* m_context = nullptr;
    VkBuffer m_buffer = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkDeviceSize m_size = 0;
    MemoryKind m_kind = MemoryKind::DeviceLocal;
    void* m_mapped = nullptr;
};

// A barrier that makes compute-shader and transfer writes visible to later
// compute-shader, transfer and indirect-command reads (whole-pipeline memory
// barrier: vkpath's stages are ordered, not overlapped).
void computeBarrier(VkCommandBuffer cmd);

}  // namespace vkpath::vk
