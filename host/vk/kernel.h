// The kernel harness: one compute pipeline built from an embedded kernel, with
// its descriptor-set layout and push-constant range taken from the SPIR-V
// itself. Kernels of the same name, workgroup size and specialisation share
// one pipeline, compiled once per context (Context::compiledKernel). Tests and the wavefront
// integrator use the same class:
//
//   vkpath::vk::Kernel fill(context, "rng_fill");
//   double ms = fill.dispatch(count, {{0, &bits}}, push);
//   auto result = bits.download<uint32_t>();
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vk/spirv_reflect.h"

namespace vkpath::vk {

class Buffer;
class Context;

struct SpecializationConstant {
    uint32_t id;
    uint32_t value;  // the 32-bit pattern: uint, int, bool (0/1) or float bits

    bool operator==(const SpecializationConstant&) const = default;
};

struct KernelOptions {
    // Threads per workgroup (specialisation constant 0, `local_size_x_id = 0`).
    uint32_t workgroupSize = 64;
    std::vector<SpecializationConstant> specialization;
};

struct BufferBinding {
    uint32_t binding;
    const Buffer* buffer;
};

class DescriptorSetPool;
struct CompiledKernel;

// A descriptor set for one kernel, holding its buffers; freed on destruction.
class DescriptorSet {
  public:
    DescriptorSet() = default;
    DescriptorSet(std::shared_ptr<DescriptorSetPool> pool, VkDescriptorSet set);
    ~DescriptorSet();
    DescriptorSet(DescriptorSet&& other) noexcept;
    DescriptorSet& operator=(DescriptorSet&& other) noexcept;
    VkDescriptorSet handle() const { return m_set; }

  private:
    std::shared_ptr<DescriptorSetPool> m_pool;
    VkDescriptorSet m_set = VK_NULL_HANDLE;
};

class Kernel {
  public:
    Kernel(Context& context, std::string_view name, const KernelOptions& options = {});
    ~Kernel();
    Kernel(const Kernel&) = delete;
    Kernel& operator=(const Kernel&) = delete;

    const std::string& name() const { return m_name; }
    uint32_t workgroupSize() const { return m_workgroupSize; }
    const SpirvReflection& reflection() const;

    // A descriptor set with every binding the kernel declares filled; throws
    // naming the kernel if one is missing, unknown or given twice.
    DescriptorSet bind(std::initializer_list<BufferBinding> buffers) {
        return bind(std::span(buffers));
    }
    DescriptorSet bind(std::span<const BufferBinding> buffers);
    // A descriptor set with every binding the kernel declares filled from
    // `available` (binding -> buffer), which may hold more; throws naming the
    // kernel and binding if one it declares is not there.
    DescriptorSet bindDeclared(const std::map<uint32_t, const Buffer*>& available);

    // Records a dispatch of at least `invocations` threads (whole workgroups);
    // `push` must be exactly the kernel's push-constant block.
    void record(VkCommandBuffer cmd, const DescriptorSet& set, uint32_t invocations,
                std::span<const std::byte> push) const;
    // Records a dispatch whose group counts the device reads from `arguments`
    // at `offset` (a VkDispatchIndirectCommand).
    void recordIndirect(VkCommandBuffer cmd, const DescriptorSet& set, const Buffer& arguments,
                        VkDeviceSize offset, std::span<const std::byte> push) const;

    // Binds, dispatches, waits; returns the device time in milliseconds
    // (0 where the device has no timestamps).
    double dispatch(uint32_t invocations, std::initializer_list<BufferBinding> buffers,
                    std::span<const std::byte> push = {});
    template <typename Push>
    double dispatch(uint32_t invocations, std::initializer_list<BufferBinding> buffers,
                    const Push& push) {
        return dispatch(invocations, buffers, std::as_bytes(std::span(&push, 1)));
    }

  private:
    void bindPipeline(VkCommandBuffer cmd, const DescriptorSet& set,
                      std::span<const std::byte> push) const;

    Context& m_context;
    std::string m_name;
    uint32_t m_workgroupSize = 0;
    std::shared_ptr<const CompiledKernel> m_compiled;
    std::shared_ptr<DescriptorSetPool> m_pool;
};

}  // namespace vkpath::vk
