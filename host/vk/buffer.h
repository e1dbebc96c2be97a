// Storage buffers in device-local memory, filled and read back through
// host-visible staging buffers (filled directly where device-local memory is
// the host's).
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace vkpath::vk {

class Context;
struct DeviceInfo;

enum class MemoryKind {
    DeviceLocal,  // where kernels read and write; reached through staging copies
    Staging,      // host-visible and coherent, for transfers
};

class Buffer {
  public:
    Buffer() = default;
    // A buffer of `size` bytes (at least 4) usable as a storage buffer, a
    // uniform texel buffer (texelView), a copy source and destination, and an
    // indirect-dispatch argument buffer; device-local ones also as
    // `extraUsage` says (acceleration structures' storage and build input).
    Buffer(Context& context, VkDeviceSize size, MemoryKind kind = MemoryKind::DeviceLocal,
           const char* debugName = nullptr, VkBufferUsageFlags extraUsage = 0);
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    // A device-local buffer holding a copy of `data`.
    template <typename T, size_t Extent>
    static Buffer fromSpan(Context& context, std::span<T, Extent> data,
                           const char* debugName = nullptr, VkBufferUsageFlags extraUsage = 0) {
        Buffer buffer(context, data.size_bytes(), MemoryKind::DeviceLocal, debugName, extraUsage);
        buffer.upload(std::as_bytes(data));
        return buffer;
    }

    VkBuffer handle() const { return m_buffer; }
    // The buffer's address for GL_EXT_buffer_reference (device-local buffers,
    // on a device with bufferDeviceAddress). Reads through an address are not
    // bounded by maxStorageBufferRange, only by the buffer's size.
    VkDeviceAddress deviceAddress() const;
    VkDeviceSize size() const { return m_size; }
    explicit operator bool() const { return m_buffer != VK_NULL_HANDLE; }
    // The device-local buffer as a uniform texel buffer of
    // VK_FORMAT_R32G32B32A32_UINT texels (a GLSL usamplerBuffer), made at the
    // first call: its whole 16-byte texels, at most maxTexelBufferElements.
    // Kernels read the scene's most-read arrays this way (shared/bvh_buffers.h
    // says why).
    VkBufferView texelView() const;

    // Copies bytes in at `offset` (staging copy and wait; a copy into the
    // mapped buffer where its memory is the host's).
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
    mutable VkBufferView m_texelView = VK_NULL_HANDLE;
    VkDeviceSize m_size = 0;
    MemoryKind m_kind = MemoryKind::DeviceLocal;
    void* m_mapped = nullptr;
    bool m_hostWritable = false;  // device-local memory the host may map: uploads go directly
};

// The largest array a kernel may read, in bytes, in each of the two ways
// kernels read scene data (shared/bvh_buffers.h):
struct BufferLimits {
    uint64_t binding;        // bound: as a texel buffer of 16-byte texels,
                             // 16 maxTexelBufferElements (2 GiB on lavapipe)
    uint64_t address;        // through its device address: one buffer, min(maxBufferSize,
                             // maxMemoryAllocationSize)
    uint64_t deviceBinding;  // `binding` as the device has it, whatever VKPATH_MAX_BINDING_BYTES
                             // says: what an array that is always bound must fit
};
// The device's limits. The environment variable VKPATH_MAX_BINDING_BYTES, when
// set, lowers `binding` (never raises it) so that tests take the address path
// with small scenes.
BufferLimits bufferLimits(const DeviceInfo& device);

// One array of a scene, for chooseAddressAccess.
struct ArrayExtent {
    const char* name;  // e.g. "BVH primitive"
    uint64_t bytes;
    uint64_t count;  // elements
};

// Whether a scene's arrays must be read by address: true when any is larger
// than limits.binding. Throws InputError, naming the array, its size and the
// limit, when one is larger than even limits.address.
bool chooseAddressAccess(std::span<const ArrayExtent> arrays, const BufferLimits& limits);

// A barrier that makes compute-shader and transfer writes visible to later
// compute-shader, transfer and indirect-command reads (whole-pipeline memory
// barrier: vkpath's stages are ordered, not overlapped).
void computeBarrier(VkCommandBuffer cmd);

}  // namespace vkpath::vk
