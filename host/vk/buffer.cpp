#include "vk/buffer.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "environment_bytes.h"
#include "format_bytes.h"
#include "input_error.h"
#include "vk/check.h"
#include "vk/context.h"

namespace vkpath::vk {

Buffer::Buffer(Context& context, VkDeviceSize size, MemoryKind kind, const char* debugName,
               VkBufferUsageFlags extraUsage)
    : m_context(&context), m_size(size), m_kind(kind) {
    const VkDeviceSize allocated = std::max<VkDeviceSize>(size, 4);
    VkBufferCreateInfo create{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    create.size = allocated;
    create.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (kind == MemoryKind::DeviceLocal)
        create.usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                        VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                        VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | extraUsage;
    const bool addressable = kind == MemoryKind::DeviceLocal && context.info().bufferDeviceAddress;
    if (addressable) create.usage |= VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    create.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkDevice device = context.device();
    VK_CHECK(vkCreateBuffer(device, &create, nullptr, &m_buffer));
    try {
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device, m_buffer, &req);
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
        flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
        if (addressable) alloc.pNext = &flags;
        if (kind == MemoryKind::DeviceLocal) {
            alloc.memoryTypeIndex =
                context.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
            // The first device-local type is also the host's on a device that
            // shares the host's memory (lavapipe, integrated GPUs): there an
            // upload is one copy, with no staging buffer to hold a second.
            constexpr VkMemoryPropertyFlags hostWritable =
                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
            m_hostWritable =
                (context.memoryTypeFlags(alloc.memoryTypeIndex) & hostWritable) == hostWritable;
        } else {
            alloc.memoryTypeIndex = context.findMemoryType(
                req.memoryTypeBits,
                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        }
        VK_CHECK(vkAllocateMemory(device, &alloc, nullptr, &m_memory));
        VK_CHECK(vkBindBufferMemory(device, m_buffer, m_memory, 0));
        if (kind == MemoryKind::Staging)
            VK_CHECK(vkMapMemory(device, m_memory, 0, VK_WHOLE_SIZE, 0, &m_mapped));
    } catch (...) {
        release();
        throw;
    }
    if (debugName && context.validationEnabled()) {
        auto setName = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
            vkGetInstanceProcAddr(context.instance(), "vkSetDebugUtilsObjectNameEXT"));
        if (setName) {
            VkDebugUtilsObjectNameInfoEXT name{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
            name.objectType = VK_OBJECT_TYPE_BUFFER;
            name.objectHandle = reinterpret_cast<uint64_t>(m_buffer);
            name.pObjectName = debugName;
            VK_CHECK(setName(device, &name));
        }
    }
}

Buffer::~Buffer() {
    release();
}

VkDeviceAddress Buffer::deviceAddress() const {
    if (m_kind != MemoryKind::DeviceLocal || !m_context->info().bufferDeviceAddress)
        throw std::logic_error(
            "buffer device address: needs a device-local buffer and bufferDeviceAddress");
    VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    info.buffer = m_buffer;
    return vkGetBufferDeviceAddress(m_context->device(), &info);
}

VkBufferView Buffer::texelView() const {
    if (m_texelView) return m_texelView;
    constexpr VkDeviceSize TEXEL_BYTES = 16;
    const VkDeviceSize texels =
        std::min<VkDeviceSize>(m_size / TEXEL_BYTES, m_context->info().maxTexelBufferElements);
    if (m_kind != MemoryKind::DeviceLocal || texels == 0)
        throw std::logic_error(fmt::format(
            "texel view: needs a device-local buffer of at least {} bytes (this one: {})",
            TEXEL_BYTES, m_size));
    VkBufferViewCreateInfo create{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    create.buffer = m_buffer;
    create.format =
        VK_FORMAT_R32G32B32A32_UINT;  // uniform texel buffers of it are required of every device
    create.offset = 0;
    create.range = texels * TEXEL_BYTES;
    VK_CHECK(vkCreateBufferView(m_context->device(), &create, nullptr, &m_texelView));
    return m_texelView;
}

Buffer::Buffer(Buffer&& other) noexcept {
    *this = std::move(other);
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        release();
        m_context = std::exchange(other.m_context, nullptr);
        m_buffer = std::exchange(other.m_buffer, VK_NULL_HANDLE);
        m_memory = std::exchange(other.m_memory, VK_NULL_HANDLE);
        m_texelView = std::exchange(other.m_texelView, VK_NULL_HANDLE);
        m_size = std::exchange(other.m_size, 0);
        m_kind = other.m_kind;
        m_hostWritable = other.m_hostWritable;
        m_mapped = std::exchange(other.m_mapped, nullptr);
    }
    return *this;
}

void Buffer::release() {
    if (!m_context) return;
    VkDevice device = m_context->device();
    if (m_mapped) vkUnmapMemory(device, m_memory);
    if (m_texelView) vkDestroyBufferView(device, m_texelView, nullptr);
    if (m_buffer) vkDestroyBuffer(device, m_buffer, nullptr);
    if (m_memory) vkFreeMemory(device, m_memory, nullptr);
    m_mapped = nullptr;
    m_texelView = VK_NULL_HANDLE;
    m_buffer = VK_NULL_HANDLE;
    m_memory = VK_NULL_HANDLE;
}

void Buffer::upload(std::span<const std::byte> bytes, VkDeviceSize offset) {
    if (offset + bytes.size() > m_size)
        throw std::out_of_range(fmt::format("upload of {} bytes at {} exceeds buffer of {}",
                                            bytes.size(), offset, m_size));
    if (bytes.empty()) return;
    if (m_kind == MemoryKind::Staging) {
        std::memcpy(static_cast<std::byte*>(m_mapped) + offset, bytes.data(), bytes.size());
        return;
    }
    if (m_hostWritable) {
        // Every submission waits for its fence (Context::submit), so no
        // command is using the buffer; the next submission makes the write
        // visible to the device (host-coherent memory).
        void* mapped = nullptr;
        VK_CHECK(vkMapMemory(m_context->device(), m_memory, offset, bytes.size(), 0, &mapped));
        std::memcpy(mapped, bytes.data(), bytes.size());
        vkUnmapMemory(m_context->device(), m_memory);
        return;
    }
    Buffer staging(*m_context, bytes.size(), MemoryKind::Staging);
    std::memcpy(staging.mapped(), bytes.data(), bytes.size());
    m_context->submit([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, offset, bytes.size()};
        vkCmdCopyBuffer(cmd, staging.handle(), m_buffer, 1, &region);
    });
}

void Buffer::download(std::span<std::byte> bytes, VkDeviceSize offset) const {
    if (offset + bytes.size() > m_size)
        throw std::out_of_range(fmt::format("download of {} bytes at {} exceeds buffer of {}",
                                            bytes.size(), offset, m_size));
    if (bytes.empty()) return;
    if (m_kind == MemoryKind::Staging) {
        std::memcpy(bytes.data(), static_cast<const std::byte*>(m_mapped) + offset, bytes.size());
        return;
    }
    Buffer staging(*m_context, bytes.size(), MemoryKind::Staging);
    m_context->submit([&](VkCommandBuffer cmd) {
        VkBufferCopy region{offset, 0, bytes.size()};
        vkCmdCopyBuffer(cmd, m_buffer, staging.handle(), 1, &region);
        // Make the transfer write visible to the host read after the fence.
        VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                             &barrier, 0, nullptr, 0, nullptr);
    });
    std::memcpy(bytes.data(), staging.mapped(), bytes.size());
}

void Buffer::clear() {
    m_context->submit(
        [&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, m_buffer, 0, VK_WHOLE_SIZE, 0); });
}

BufferLimits bufferLimits(const DeviceInfo& device) {
    // A bound scene array is read as a texel buffer of 16-byte texels
    // (Buffer::texelView; no kernel binds one as a storage buffer, whose
    // range, maxStorageBufferRange, is 128 MiB on lavapipe against its
    // texel buffers' 2 GiB).
    const uint64_t binding = uint64_t(device.maxTexelBufferElements) * 16;
    BufferLimits limits{binding, std::min(device.maxBufferSize, device.maxMemoryAllocationSize),
                        binding};
    if (const std::optional<uint64_t> set = environmentBytes("VKPATH_MAX_BINDING_BYTES"))
        limits.binding = std::min<uint64_t>(limits.binding, *set);
    return limits;
}

bool chooseAddressAccess(std::span<const ArrayExtent> arrays, const BufferLimits& limits) {
    bool byAddress = false;
    for (const ArrayExtent& a : arrays) {
        if (a.bytes > limits.address)
            throw InputError(
                fmt::format("scene too large for the device: the {} array would be {} ({} "
                            "elements), more than the {} "
                            "one buffer may hold (maxBufferSize, maxMemoryAllocationSize)",
                            a.name, formatBytes(a.bytes), a.count, formatBytes(limits.address)));
        byAddress = byAddress || a.bytes > limits.binding;
    }
    return byAddress;
}

void computeBarrier(VkCommandBuffer cmd) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                            VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                            VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                             VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                         0, 1, &barrier, 0, nullptr, 0, nullptr);
}

}  // namespace vkpath::vk
