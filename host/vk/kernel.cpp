#include "vk/kernel.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/embedded_shaders.h"
#include "vk/spirv_no_contraction.h"
#include "vk/timestamps.h"

namespace vkpath::vk {

// The Vulkan descriptor type of a binding the SPIR-V declares.
static VkDescriptorType descriptorType(DescriptorKind kind) {
    switch (kind) {
        case DescriptorKind::StorageBuffer:
            return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        case DescriptorKind::UniformBuffer:
            return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        case DescriptorKind::UniformTexelBuffer:
            return VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    }
    throw std::logic_error("unknown descriptor kind");
}

// Descriptor pools of one kernel layout; grows by whole pools when one is full.
class DescriptorSetPool {
  public:
    // `perSet`: how many descriptors of each type one set holds.
    DescriptorSetPool(VkDevice device, VkDescriptorSetLayout layout,
                      std::map<VkDescriptorType, uint32_t> perSet)
        : m_device(device), m_layout(layout), m_perSet(std::move(perSet)) {}
    ~DescriptorSetPool() {
        for (VkDescriptorPool pool : m_pools) vkDestroyDescriptorPool(m_device, pool, nullptr);
    }

    std::pair<VkDescriptorSet, VkDescriptorPool> allocate() {
        if (!m_pools.empty()) {
            if (VkDescriptorSet set = tryAllocate(m_pools.back())) return {set, m_pools.back()};
        }
        addPool();
        VkDescriptorSet set = tryAllocate(m_pools.back());
        if (!set) throw std::runtime_error("descriptor set allocation failed in a new pool");
        return {set, m_pools.back()};
    }

    void free(VkDescriptorSet set) {
        // Sets remember nothing of their pool; try each (there are few).
        for (VkDescriptorPool pool : m_pools) {
            if (m_owner.contains({pool, set})) {
                vkFreeDescriptorSets(m_device, pool, 1, &set);
                m_owner.erase({pool, set});
                return;
            }
        }
    }

  private:
    static constexpr uint32_t SETS_PER_POOL = 32;

    VkDescriptorSet tryAllocate(VkDescriptorPool pool) {
        VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        alloc.descriptorPool = pool;
        alloc.descriptorSetCount = 1;
        alloc.pSetLayouts = &m_layout;
        VkDescriptorSet set = VK_NULL_HANDLE;
        const VkResult result = vkAllocateDescriptorSets(m_device, &alloc, &set);
        if (result == VK_ERROR_OUT_OF_POOL_MEMORY || result == VK_ERROR_FRAGMENTED_POOL)
            return VK_NULL_HANDLE;
        VK_CHECK(result);
        m_owner.insert({pool, set});
        return set;
    }

    void addPool() {
        std::vector<VkDescriptorPoolSize> sizes;
        for (const auto& [type, count] : m_perSet) sizes.push_back({type, count * SETS_PER_POOL});
        VkDescriptorPoolCreateInfo create{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        create.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
        create.maxSets = SETS_PER_POOL;
        create.poolSizeCount = static_cast<uint32_t>(sizes.size());
        create.pPoolSizes = sizes.data();
        VkDescriptorPool pool = VK_NULL_HANDLE;
        VK_CHECK(vkCreateDescriptorPool(m_device, &create, nullptr, &pool));
        m_pools.push_back(pool);
    }

    VkDevice m_device;
    VkDescriptorSetLayout m_layout;
    std::map<VkDescriptorType, uint32_t> m_perSet;
    std::vector<VkDescriptorPool> m_pools;
    std::set<std::pair<VkDescriptorPool, VkDescriptorSet>> m_owner;
};

DescriptorSet::DescriptorSet(std::shared_ptr<DescriptorSetPool> pool, VkDescriptorSet set)
    : m_pool(std::move(pool)), m_set(set) {}

DescriptorSet::~DescriptorSet() {
    if (m_pool && m_set) m_pool->free(m_set);
}

DescriptorSet::DescriptorSet(DescriptorSet&& other) noexcept
    : m_pool(std::move(other.m_pool)), m_set(std::exchange(other.m_set, VK_NULL_HANDLE)) {}

DescriptorSet& DescriptorSet::operator=(DescriptorSet&& other) noexcept {
    if (this != &other) {
        if (m_pool && m_set) m_pool->free(m_set);
        m_pool = std::move(other.m_pool);
        m_set = std::exchange(other.m_set, VK_NULL_HANDLE);
    }
    return *this;
}

// A kernel's Vulkan objects, shared by every Kernel built with the same name,
// workgroup size and specialisation in one context (Context::compiledKernel).
struct CompiledKernel {
    VkDevice device = VK_NULL_HANDLE;
    SpirvReflection reflection;
    std::map<VkDescriptorType, uint32_t> perSet;
    VkShaderModule module = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout pipelineLayout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;

    CompiledKernel(Context& context, const std::string& name, uint32_t workgroupSize,
                   const std::vector<SpecializationConstant>& specialization);
    ~CompiledKernel() { release(); }
    CompiledKernel(const CompiledKernel&) = delete;
    CompiledKernel& operator=(const CompiledKernel&) = delete;

  private:
    void release();
};

CompiledKernel::CompiledKernel(Context& context, const std::string& name, uint32_t workgroupSize,
                               const std::vector<SpecializationConstant>& specialization)
    : device(context.device()) {
    const std::vector<uint32_t> spirv = decorateNoContraction(shaders::findKernel(name));
    reflection = reflectSpirv(spirv);
    const DeviceInfo& info = context.info();
    if (workgroupSize == 0 || workgroupSize > info.maxWorkgroupSize[0] ||
        workgroupSize > info.maxWorkgroupInvocations)
        throw std::invalid_argument(
            fmt::format("kernel {}: workgroup size {} is not supported (max {})", name,
                        workgroupSize, info.maxWorkgroupSize[0]));
    if (reflection.pushConstantSize > info.maxPushConstantsSize)
        throw std::invalid_argument(
            fmt::format("kernel {}: {} bytes of push constants exceed the device's {}", name,
                        reflection.pushConstantSize, info.maxPushConstantsSize));
    try {
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = spirv.size() * sizeof(uint32_t);
        moduleInfo.pCode = spirv.data();
        VK_CHECK(vkCreateShaderModule(device, &moduleInfo, nullptr, &module));

        std::vector<VkDescriptorSetLayoutBinding> bindings;
        for (const SpirvBinding& b : reflection.bindings) {
            if (b.set != 0)
                throw std::invalid_argument(
                    fmt::format("kernel {}: only descriptor set 0 is supported", name));
            VkDescriptorSetLayoutBinding binding{};
            binding.binding = b.binding;
            binding.descriptorType = descriptorType(b.kind);
            binding.descriptorCount = 1;
            binding.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
            bindings.push_back(binding);
            ++perSet[binding.descriptorType];
        }
        VkDescriptorSetLayoutCreateInfo setInfo{
            VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        setInfo.bindingCount = static_cast<uint32_t>(bindings.size());
        setInfo.pBindings = bindings.data();
        VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout));

        VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, reflection.pushConstantSize};
        VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layoutInfo.setLayoutCount = 1;
        layoutInfo.pSetLayouts = &setLayout;
        layoutInfo.pushConstantRangeCount = reflection.pushConstantSize ? 1 : 0;
        layoutInfo.pPushConstantRanges = &range;
        VK_CHECK(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &pipelineLayout));

        std::vector<SpecializationConstant> constants = specialization;
        constants.push_back({0, workgroupSize});
        std::vector<VkSpecializationMapEntry> entries;
        std::vector<uint32_t> values;
        for (const SpecializationConstant& c : constants) {
            entries.push_back(
                {c.id, static_cast<uint32_t>(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
            values.push_back(c.value);
        }
        VkSpecializationInfo specializationInfo{static_cast<uint32_t>(entries.size()),
                                                entries.data(), values.size() * sizeof(uint32_t),
                                                values.data()};

        VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipelineInfo.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipelineInfo.stage.module = module;
        pipelineInfo.stage.pName = "main";
        pipelineInfo.stage.pSpecializationInfo = &specializationInfo;
        pipelineInfo.layout = pipelineLayout;
        VK_CHECK(vkCreateComputePipelines(device, context.pipelineCache(), 1, &pipelineInfo,
                                          nullptr, &pipeline));
    } catch (...) {
        release();
        throw;
    }
}

void CompiledKernel::release() {
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    if (pipelineLayout) vkDestroyPipelineLayout(device, pipelineLayout, nullptr);
    if (setLayout) vkDestroyDescriptorSetLayout(device, setLayout, nullptr);
    if (module) vkDestroyShaderModule(device, module, nullptr);
    pipeline = VK_NULL_HANDLE;
    pipelineLayout = VK_NULL_HANDLE;
    setLayout = VK_NULL_HANDLE;
    module = VK_NULL_HANDLE;
}

// What makes two kernels' pipelines the same: the embedded SPIR-V (by name),
// the workgroup size and every specialisation constant.
static std::string compiledKernelKey(std::string_view name, const KernelOptions& options) {
    std::string key = fmt::format("{} {}", name, options.workgroupSize);
    for (const SpecializationConstant& c : options.specialization)
        key += fmt::format(" {}={}", c.id, c.value);
    return key;
}

Kernel::Kernel(Context& context, std::string_view name, const KernelOptions& options)
    : m_context(context), m_name(name), m_workgroupSize(options.workgroupSize) {
    m_compiled = context.compiledKernel(compiledKernelKey(name, options), [&] {
        return std::make_shared<const CompiledKernel>(context, m_name, m_workgroupSize,
                                                      options.specialization);
    });
    m_pool = std::make_shared<DescriptorSetPool>(context.device(), m_compiled->setLayout,
                                                 m_compiled->perSet);
}

Kernel::~Kernel() {
    // Sets still allocated hold the pool; the pipeline stays with the context.
    m_pool.reset();
}

const SpirvReflection& Kernel::reflection() const {
    return m_compiled->reflection;
}

DescriptorSet Kernel::bindDeclared(const std::map<uint32_t, const Buffer*>& available) {
    std::vector<BufferBinding> buffers;
    for (const SpirvBinding& b : m_compiled->reflection.bindings) {
        const auto it = available.find(b.binding);
        if (it == available.end())
            throw std::invalid_argument(
                fmt::format("kernel {}: binding {} has no buffer", m_name, b.binding));
        buffers.push_back({b.binding, it->second});
    }
    return bind(buffers);
}

DescriptorSet Kernel::bind(std::span<const BufferBinding> buffers) {
    std::set<uint32_t> declared;
    for (const SpirvBinding& b : m_compiled->reflection.bindings) declared.insert(b.binding);
    std::set<uint32_t> given;
    for (const BufferBinding& b : buffers) {
        if (!declared.contains(b.binding))
            throw std::invalid_argument(
                fmt::format("kernel {} has no binding {}", m_name, b.binding));
        if (!given.insert(b.binding).second)
            throw std::invalid_argument(
                fmt::format("kernel {}: binding {} given twice", m_name, b.binding));
        if (!b.buffer || !*b.buffer)
            throw std::invalid_argument(
                fmt::format("kernel {}: binding {} has no buffer", m_name, b.binding));
    }
    for (uint32_t b : declared)
        if (!given.contains(b))
            throw std::invalid_argument(
                fmt::format("kernel {}: binding {} is not bound", m_name, b));

    auto [set, pool] = m_pool->allocate();
    DescriptorSet result(m_pool, set);
    std::vector<VkDescriptorBufferInfo> infos;
    infos.reserve(buffers.size());
    std::vector<VkBufferView> views;
    views.reserve(buffers.size());
    std::vector<VkWriteDescriptorSet> writes;
    for (const BufferBinding& b : buffers) {
        infos.push_back({b.buffer->handle(), 0, VK_WHOLE_SIZE});
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = set;
        write.dstBinding = b.binding;
        write.descriptorCount = 1;
        const auto it = std::find_if(m_compiled->reflection.bindings.begin(),
                                     m_compiled->reflection.bindings.end(),
                                     [&](const SpirvBinding& s) { return s.binding == b.binding; });
        write.descriptorType = descriptorType(it->kind);
        if (it->kind == DescriptorKind::UniformTexelBuffer) {
            views.push_back(b.buffer->texelView());
            write.pTexelBufferView = &views.back();
        } else {
            write.pBufferInfo = &infos.back();
        }
        writes.push_back(write);
    }
    vkUpdateDescriptorSets(m_context.device(), static_cast<uint32_t>(writes.size()), writes.data(),
                           0, nullptr);
    return result;
}

void Kernel::bindPipeline(VkCommandBuffer cmd, const DescriptorSet& set,
                          std::span<const std::byte> push) const {
    if (push.size() != m_compiled->reflection.pushConstantSize)
        throw std::invalid_argument(
            fmt::format("kernel {}: {} bytes of push constants given, the kernel declares {}",
                        m_name, push.size(), m_compiled->reflection.pushConstantSize));
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_compiled->pipeline);
    VkDescriptorSet handle = set.handle();
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_compiled->pipelineLayout, 0, 1,
                            &handle, 0, nullptr);
    if (!push.empty())
        vkCmdPushConstants(cmd, m_compiled->pipelineLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                           static_cast<uint32_t>(push.size()), push.data());
}

void Kernel::record(VkCommandBuffer cmd, const DescriptorSet& set, uint32_t invocations,
                    std::span<const std::byte> push) const {
    const uint32_t groups = (invocations + m_workgroupSize - 1) / m_workgroupSize;
    if (groups > m_context.info().maxWorkgroupCount[0])
        throw std::invalid_argument(
            fmt::format("kernel {}: {} invocations need {} workgroups, the device allows {}",
                        m_name, invocations, groups, m_context.info().maxWorkgroupCount[0]));
    bindPipeline(cmd, set, push);
    if (groups > 0) vkCmdDispatch(cmd, groups, 1, 1);
}

void Kernel::recordIndirect(VkCommandBuffer cmd, const DescriptorSet& set, const Buffer& arguments,
                            VkDeviceSize offset, std::span<const std::byte> push) const {
    bindPipeline(cmd, set, push);
    vkCmdDispatchIndirect(cmd, arguments.handle(), offset);
}

double Kernel::dispatch(uint32_t invocations, std::initializer_list<BufferBinding> buffers,
                        std::span<const std::byte> push) {
    DescriptorSet set = bind(buffers);
    TimestampPool timestamps(m_context, 1);
    m_context.submit([&](VkCommandBuffer cmd) {
        timestamps.reset(cmd);
        computeBarrier(cmd);  // earlier uploads are visible to the kernel
        const uint32_t interval = timestamps.begin(cmd, m_name);
        record(cmd, set, invocations, push);
        timestamps.end(cmd, interval);
        computeBarrier(cmd);  // the kernel's writes are visible to later copies
    });
    const auto results = timestamps.results();
    return results.empty() ? 0.0 : results.front().milliseconds;
}

}  // namespace vkpath::vk
