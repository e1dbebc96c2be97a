// The Vulkan compute context: instance (with optional validation), the chosen
// physical device, one compute queue, one-shot command submission and the
// on-disk pipeline cache.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace vkpath::vk {

struct CompiledKernel;

struct ContextOptions {
    // Enables VK_LAYER_KHRONOS_validation and a debug messenger that prints every
    // warning and error and counts them (validationMessageCount()).
    bool validation = false;
    // Index into the physical-device list (as `vkpath info` prints it). When
    // unset, the environment variable VKPATH_DEVICE_INDEX is read; when that is
    // unset too, the best device is picked: discrete > integrated > virtual > CPU.
    std::optional<uint32_t> deviceIndex;
    // Load and save the pipeline cache under pipelineCacheDirectory().
    bool pipelineCache = true;
    // Called with each validation warning or error, on the thread whose Vulkan
    // call caused it (tests turn these into test failures).
    std::function<void(const char* message)> onValidationMessage;
};

// What vkpath needs to know about a physical device.
struct DeviceInfo {
    uint32_t index = 0;
    std::string name;
    std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
    std::string driverName;
    std::string driverInfo;
    uint32_t apiVersion = 0;
    uint32_t driverVersion = 0;
    uint32_t vendorId = 0;
    uint32_t deviceId = 0;
    std::array<uint8_t, VK_UUID_SIZE> pipelineCacheUuid{};
    std::array<uint32_t, 3> maxWorkgroupSize{};
    std::array<uint32_t, 3> maxWorkgroupCount{};
    uint32_t maxWorkgroupInvocations = 0;
    uint64_t maxStorageBufferRange = 0;    // bytes one storage-buffer binding may span
    uint32_t maxTexelBufferElements = 0;   // texels one texel-buffer view may span
    uint64_t maxMemoryAllocationSize = 0;  // bytes, one allocation
    uint64_t maxBufferSize = 0;  // bytes, one buffer (maxMemoryAllocationSize before Vulkan 1.3)
    uint32_t maxPushConstantsSize = 0;
    uint32_t subgroupSize = 0;
    bool shaderFloat64 = false;
    bool shaderInt64 = false;
    bool scalarBlockLayout = false;
    bool bufferDeviceAddress = false;
    // The kernels declare the SignedZeroInfNanPreserve execution mode for
    // 32-bit floats (shaders/stages/lib/float_controls.glsl): the device must honour it.
    bool signedZeroInfNanPreserveFloat32 = false;
    // Hardware ray tracing from compute shaders: VK_KHR_ray_query and
    // VK_KHR_acceleration_structure (with VK_KHR_deferred_host_operations,
    // which it requires) are there and their features on.
    bool rayQuery = false;
    bool timestamps = false;         // the compute queue has timestampValidBits > 0
    float timestampPeriodNs = 0;     // nanoseconds per timestamp tick
    uint64_t deviceLocalMemory = 0;  // bytes, largest device-local heap

    std::string apiVersionString() const;
};

// Advice for a device whose driver is known to be much slower than one the
// user can install (lavapipe before Mesa 25, measured in
// docs/BENCHMARKS.md); empty when there is none.
std::string driverAdvice(const DeviceInfo& device);

// Physical devices visible to the loader, in enumeration order, and the index
// the default choice would take.
std::vector<DeviceInfo> listDevices(bool validation = false);
uint32_t preferredDeviceIndex(const std::vector<DeviceInfo>& devices);

// Where the pipeline cache lives: $VKPATH_CACHE_DIR, else $XDG_CACHE_HOME/vkpath,
// else $HOME/.cache/vkpath.
std::filesystem::path pipelineCacheDirectory();

class Context {
  public:
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return m_instance; }
    VkPhysicalDevice physicalDevice() const { return m_physicalDevice; }
    VkDevice device() const { return m_device; }
    VkQueue queue() const { return m_queue; }
    uint32_t queueFamily() const { return m_queueFamily; }
    VkPipelineCache pipelineCache() const { return m_pipelineCache; }
    const DeviceInfo& info() const { return m_info; }
    bool validationEnabled() const { return m_validation; }

    // Warnings and errors reported by the validation layer so far.
    uint32_t validationMessageCount() const { return m_validationMessages.load(); }

    // Records commands with `record`, submits them to the compute queue and
    // waits for completion.
    void submit(const std::function<void(VkCommandBuffer)>& record);

    // A memory type index with all of `required` among `typeBits`; throws if none.
    uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;
    // The property flags of memory type `type`.
    VkMemoryPropertyFlags memoryTypeFlags(uint32_t type) const {
        return m_memory.memoryTypes[type].propertyFlags;
    }
    // Like findMemoryType but returns nullopt instead of throwing.
    std::optional<uint32_t> tryFindMemoryType(uint32_t typeBits,
                                              VkMemoryPropertyFlags required) const;

    // Writes the pipeline cache to disk now (also done on destruction).
    void savePipelineCache() const;

    // The compiled kernel under `key` (vk/kernel.cpp says what it holds),
    // compiled by `compile` the first time. A driver may take seconds per
    // pipeline (lavapipe: 0.5-1.5 s for a wavefront stage, most of it outside
    // its pipeline cache), and renderers of one scene, or of scenes with the
    // same features, ask for the same pipelines: the context keeps the
    // KEPT_KERNELS most recently used.
    std::shared_ptr<const CompiledKernel> compiledKernel(
        const std::string& key,
        const std::function<std::shared_ptr<const CompiledKernel>()>& compile);
    static constexpr size_t KEPT_KERNELS = 24;

  private:
    static VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(
        VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
        const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
    void destroy();
    void createInstance();
    void pickDevice(std::optional<uint32_t> requested);
    void createDevice();
    void loadPipelineCache();
    std::filesystem::path pipelineCacheFile() const;

    bool m_validation = false;
    bool m_usePipelineCache = true;
    std::function<void(const char*)> m_onValidationMessage;
    std::atomic<uint32_t> m_validationMessages{0};
    VkInstance m_instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT m_messenger = VK_NULL_HANDLE;
    VkPhysicalDevice m_physicalDevice = VK_NULL_HANDLE;
    VkDevice m_device = VK_NULL_HANDLE;
    VkQueue m_queue = VK_NULL_HANDLE;
    uint32_t m_queueFamily = 0;
    VkCommandPool m_commandPool = VK_NULL_HANDLE;
    VkFence m_fence = VK_NULL_HANDLE;
    VkPipelineCache m_pipelineCache = VK_NULL_HANDLE;
    std::mutex m_keptKernelsMutex;
    // Most recently used first.
    std::list<std::pair<std::string, std::shared_ptr<const CompiledKernel>>> m_keptKernels;
    VkPhysicalDeviceMemoryProperties m_memory{};
    DeviceInfo m_info;
};

}  // namespace vkpath::vk
