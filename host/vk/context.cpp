#include "vk/context.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include "input_error.h"
#include "vk/check.h"

namespace vkpath::vk {
namespace {

constexpr const char* VALIDATION_LAYER = "VK_LAYER_KHRONOS_validation";

bool hasLayer(const char* name) {
    uint32_t count = 0;
    VK_CHECK(vkEnumerateInstanceLayerProperties(&count, nullptr));
    std::vector<VkLayerProperties> layers(count);
    VK_CHECK(vkEnumerateInstanceLayerProperties(&count, layers.data()));
    return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
        return std::strcmp(l.layerName, name) == 0;
    });
}

const char* deviceTypeName(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return "discrete";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return "integrated";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return "virtual";
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return "cpu";
        default:
            return "other";
    }
}

// Higher is preferred.
int deviceTypeRank(const std::string& type) {
    if (type == "discrete") return 4;
    if (type == "integrated") return 3;
    if (type == "virtual") return 2;
    if (type == "cpu") return 1;
    return 0;
}

// The queue family used for compute: the first with compute and timestamps,
// else the first with compute.
std::optional<uint32_t> computeQueueFamily(VkPhysicalDevice device, uint32_t* timestampBits) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    std::optional<uint32_t> fallback;
    for (uint32_t i = 0; i < count; ++i) {
        if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
        if (families[i].timestampValidBits > 0) {
            *timestampBits = families[i].timestampValidBits;
            return i;
        }
        if (!fallback) fallback = i;
    }
    *timestampBits = 0;
    return fallback;
}

DeviceInfo describe(VkPhysicalDevice device, uint32_t index) {
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceFloatControlsProperties floatControls{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES};
    driver.pNext = &floatControls;
    VkPhysicalDeviceSubgroupProperties subgroup{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    subgroup.pNext = &driver;
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = &subgroup;
    // Buffer size limits: maxMemoryAllocationSize (Vulkan 1.1 core) and
    // maxBufferSize (1.3 core; only chained where the device has 1.3).
    VkPhysicalDeviceMaintenance3Properties maintenance3{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceMaintenance4Properties maintenance4{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_PROPERTIES};
    VkPhysicalDeviceProperties basic;
    vkGetPhysicalDeviceProperties(device, &basic);
    maintenance3.pNext = props.pNext;
    props.pNext = &maintenance3;
    const bool vulkan13 = basic.apiVersion >= VK_API_VERSION_1_3;
    if (vulkan13) {
        maintenance4.pNext = props.pNext;
        props.pNext = &maintenance4;
    }
    vkGetPhysicalDeviceProperties2(device, &props);

    VkPhysicalDeviceVulkan12Features features12{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    const bool vulkan12 = props.properties.apiVersion >= VK_API_VERSION_1_2;
    if (vulkan12) features.pNext = &features12;
    vkGetPhysicalDeviceFeatures2(device, &features);

    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(device, &memory);

    uint32_t extensionCount = 0;
    vkEnumerateDeviceExtensionProperties(device, nullptr, &extensionCount, nullptr);
    std::vector<VkExtensionProperties> extensions(extensionCount);
    vkEnumerateDeviceExtensionProperties(device, nullptr, &extensionCount, extensions.data());
    auto hasExtension = [&](const char* name) {
        return std::any_of(extensions.begin(), extensions.end(), [name](const auto& e) {
            return std::strcmp(e.extensionName, name) == 0;
        });
    };
    bool rayQuery = false;
    if (vulkan12 && hasExtension(VK_KHR_RAY_QUERY_EXTENSION_NAME) &&
        hasExtension(VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) &&
        hasExtension(VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME)) {
        VkPhysicalDeviceRayQueryFeaturesKHR query{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
        VkPhysicalDeviceAccelerationStructureFeaturesKHR structures{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
        query.pNext = &structures;
        VkPhysicalDeviceFeatures2 rayFeatures{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        rayFeatures.pNext = &query;
        vkGetPhysicalDeviceFeatures2(device, &rayFeatures);
        rayQuery = query.rayQuery && structures.accelerationStructure;
    }

    const VkPhysicalDeviceLimits& limits = props.properties.limits;
    DeviceInfo info;
    info.index = index;
    info.name = props.properties.deviceName;
    info.type = deviceTypeName(props.properties.deviceType);
    info.driverName = driver.driverName;
    info.driverInfo = driver.driverInfo;
    info.apiVersion = props.properties.apiVersion;
    info.driverVersion = props.properties.driverVersion;
    info.vendorId = props.properties.vendorID;
    info.deviceId = props.properties.deviceID;
    std::copy(std::begin(props.properties.pipelineCacheUUID),
              std::end(props.properties.pipelineCacheUUID), info.pipelineCacheUuid.begin());
    std::copy(std::begin(limits.maxComputeWorkGroupSize), std::end(limits.maxComputeWorkGroupSize),
              info.maxWorkgroupSize.begin());
    std::copy(std::begin(limits.maxComputeWorkGroupCount),
              std::end(limits.maxComputeWorkGroupCount), info.maxWorkgroupCount.begin());
    info.maxWorkgroupInvocations = limits.maxComputeWorkGroupInvocations;
    info.maxStorageBufferRange = limits.maxStorageBufferRange;
    info.maxTexelBufferElements = limits.maxTexelBufferElements;
    info.maxMemoryAllocationSize = maintenance3.maxMemoryAllocationSize;
    info.maxBufferSize =
        vulkan13 ? maintenance4.maxBufferSize : maintenance3.maxMemoryAllocationSize;
    info.maxPushConstantsSize = limits.maxPushConstantsSize;
    info.subgroupSize = subgroup.subgroupSize;
    info.shaderFloat64 = features.features.shaderFloat64;
    info.shaderInt64 = features.features.shaderInt64;
    info.scalarBlockLayout = vulkan12 && features12.scalarBlockLayout;
    info.bufferDeviceAddress = vulkan12 && features12.bufferDeviceAddress;
    info.signedZeroInfNanPreserveFloat32 =
        vulkan12 && floatControls.shaderSignedZeroInfNanPreserveFloat32;
    uint32_t timestampBits = 0;
    computeQueueFamily(device, &timestampBits);
    info.rayQuery = rayQuery;
    info.timestamps = timestampBits > 0;
    info.timestampPeriodNs = limits.timestampPeriod;
    for (uint32_t h = 0; h < memory.memoryHeapCount; ++h) {
        if (memory.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            info.deviceLocalMemory =
                std::max<uint64_t>(info.deviceLocalMemory, memory.memoryHeaps[h].size);
    }
    return info;
}

// Why a device cannot run vkpath, or empty if it can.
std::string unsuitableReason(const DeviceInfo& info) {
    if (info.apiVersion < VK_API_VERSION_1_2) return "Vulkan 1.2 is required";
    if (!info.scalarBlockLayout) return "scalarBlockLayout is required";
    // The BVH kernels declare buffer references (GL_EXT_buffer_reference) for
    // scenes larger than a storage-buffer binding (shared/bvh_buffers.h).
    if (!info.bufferDeviceAddress) return "bufferDeviceAddress is required";
    // The kernels' feature bits are a 64-bit integer (shared/features.h).
    if (!info.shaderInt64) return "shaderInt64 is required";
    // Without it a compiler may assume no NaN or infinity exists and fold away
    // the kernels' non-finite checks.
    if (!info.signedZeroInfNanPreserveFloat32)
        return "shaderSignedZeroInfNanPreserveFloat32 is required";
    return {};
}

VkInstance createBareInstance(bool validation, const void* next) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "vkpath";
    app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
    app.pEngineName = "vkpath";
    app.apiVersion = VK_API_VERSION_1_2;

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    if (validation) {
        if (!hasLayer(VALIDATION_LAYER))
            throw std::runtime_error(
                "validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                "(Debian package vulkan-validationlayers)");
        layers.push_back(VALIDATION_LAYER);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    }
    VkInstanceCreateInfo create{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    create.pNext = next;
    create.pApplicationInfo = &app;
    create.enabledLayerCount = static_cast<uint32_t>(layers.size());
    create.ppEnabledLayerNames = layers.data();
    create.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    create.ppEnabledExtensionNames = extensions.data();
    VkInstance instance = VK_NULL_HANDLE;
    VK_CHECK(vkCreateInstance(&create, nullptr, &instance));
    return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
    return devices;
}

std::optional<uint32_t> deviceIndexFromEnvironment() {
    const char* text = std::getenv("VKPATH_DEVICE_INDEX");
    if (!text || !*text) return std::nullopt;
    char* end = nullptr;
    const unsigned long value = std::strtoul(text, &end, 10);
    if (*end != '\0' || value > 0xffffffffu)
        throw InputError(fmt::format("VKPATH_DEVICE_INDEX='{}' is not a device index", text));
    return static_cast<uint32_t>(value);
}

}  // namespace

std::string DeviceInfo::apiVersionString() const {
    return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(apiVersion),
                       VK_API_VERSION_MINOR(apiVersion), VK_API_VERSION_PATCH(apiVersion));
}

std::string driverAdvice(const DeviceInfo& device) {
    // lavapipe names itself "llvmpipe" and puts "Mesa X.Y.Z ..." in driverInfo.
    if (device.driverName != "llvmpipe") return "";
    const size_t at = device.driverInfo.find("Mesa ");
    if (at == std::string::npos) return "";
    const int major = std::atoi(device.driverInfo.c_str() + at + 5);
    if (major <= 0 || major >= 25) return "";
    return fmt::format(
        "lavapipe from Mesa {}: Mesa 25 renders about 2.5x faster with the same image (on Debian "
        "12, tools/install-deps "
        "installs it from bookworm-backports; docs/BENCHMARKS.md)",
        device.driverInfo.substr(at + 5, device.driverInfo.find(' ', at + 5) - (at + 5)));
}

std::vector<DeviceInfo> listDevices(bool validation) {
    VkInstance instance = createBareInstance(validation, nullptr);
    std::vector<DeviceInfo> result;
    try {
        const auto devices = physicalDevices(instance);
        for (uint32_t i = 0; i < devices.size(); ++i) result.push_back(describe(devices[i], i));
    } catch (...) {
        vkDestroyInstance(instance, nullptr);
        throw;
    }
    vkDestroyInstance(instance, nullptr);
    return result;
}

uint32_t preferredDeviceIndex(const std::vector<DeviceInfo>& devices) {
    std::optional<uint32_t> best;
    for (const DeviceInfo& d : devices) {
        if (!unsuitableReason(d).empty()) continue;
        if (!best || deviceTypeRank(d.type) > deviceTypeRank(devices[*best].type)) best = d.index;
    }
    if (!best)
        throw std::runtime_error(
            "no Vulkan 1.2 device with scalarBlockLayout, bufferDeviceAddress, shaderInt64 and "
            "shaderSignedZeroInfNanPreserveFloat32 was found");
    return *best;
}

std::filesystem::path pipelineCacheDirectory() {
    if (const char* dir = std::getenv("VKPATH_CACHE_DIR"); dir && *dir) return dir;
    if (const char* dir = std::getenv("XDG_CACHE_HOME"); dir && *dir)
        return std::filesystem::path(dir) / "vkpath";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::filesystem::path(home) / ".cache" / "vkpath";
    return {};
}

Context::Context(const ContextOptions& options)
    : m_validation(options.validation),
      m_usePipelineCache(options.pipelineCache),
      m_onValidationMessage(options.onValidationMessage) {
    createInstance();
    try {
        pickDevice(options.deviceIndex ? options.deviceIndex : deviceIndexFromEnvironment());
        createDevice();
        loadPipelineCache();
    } catch (...) {
        destroy();
        throw;
    }
}

Context::~Context() {
    destroy();
}

void Context::destroy() {
    if (m_device) {
        vkDeviceWaitIdle(m_device);
        m_keptKernels.clear();
        if (m_pipelineCache) {
            try {
                savePipelineCache();
            } catch (const std::exception& e) {
                std::fprintf(stderr, "vkpath: warning: pipeline cache not saved: %s\n", e.what());
            }
            vkDestroyPipelineCache(m_device, m_pipelineCache, nullptr);
        }
        if (m_fence) vkDestroyFence(m_device, m_fence, nullptr);
        if (m_commandPool) vkDestroyCommandPool(m_device, m_commandPool, nullptr);
        vkDestroyDevice(m_device, nullptr);
    }
    if (m_messenger) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(m_instance, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(m_instance, m_messenger, nullptr);
    }
    if (m_instance) vkDestroyInstance(m_instance, nullptr);
    m_pipelineCache = VK_NULL_HANDLE;
    m_fence = VK_NULL_HANDLE;
    m_commandPool = VK_NULL_HANDLE;
    m_device = VK_NULL_HANDLE;
    m_messenger = VK_NULL_HANDLE;
    m_instance = VK_NULL_HANDLE;
}

std::shared_ptr<const CompiledKernel> Context::compiledKernel(
    const std::string& key, const std::function<std::shared_ptr<const CompiledKernel>()>& compile) {
    const std::lock_guard lock(m_keptKernelsMutex);
    const auto kept = std::find_if(m_keptKernels.begin(), m_keptKernels.end(),
                                   [&](const auto& entry) { return entry.first == key; });
    if (kept != m_keptKernels.end()) {
        m_keptKernels.splice(m_keptKernels.begin(), m_keptKernels, kept);
        return kept->second;
    }
    std::shared_ptr<const CompiledKernel> compiled = compile();
    m_keptKernels.emplace_front(key, compiled);
    if (m_keptKernels.size() > KEPT_KERNELS) m_keptKernels.pop_back();
    return compiled;
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::debugCallback(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT /*types*/,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* self = static_cast<Context*>(user);
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        self->m_validationMessages.fetch_add(1);
        std::fprintf(
            stderr, "vkpath: validation %s: %s\n",
            severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
            data->pMessage);
        if (self->m_onValidationMessage) self->m_onValidationMessage(data->pMessage);
    }
    return VK_FALSE;
}

void Context::createInstance() {
    VkDebugUtilsMessengerCreateInfoEXT messenger{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger.pfnUserCallback = &Context::debugCallback;
    messenger.pUserData = this;

    // Synchronisation validation catches missing barriers between the
    // wavefront stages, which the core checks do not.
    const VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    features.pNext = &messenger;

    m_instance = createBareInstance(m_validation, m_validation ? &features : nullptr);
    if (m_validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(m_instance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) throw std::runtime_error("vkCreateDebugUtilsMessengerEXT is not available");
        VK_CHECK(create(m_instance, &messenger, nullptr, &m_messenger));
    }
}

void Context::pickDevice(std::optional<uint32_t> requested) {
    const auto devices = physicalDevices(m_instance);
    if (devices.empty())
        throw std::runtime_error("no Vulkan device found (is mesa-vulkan-drivers installed?)");
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], i));
    uint32_t index = 0;
    if (requested) {
        if (*requested >= devices.size())
            throw InputError(fmt::format("device index {} is out of range: {} device(s) found",
                                         *requested, devices.size()));
        if (auto why = unsuitableReason(infos[*requested]); !why.empty())
            throw std::runtime_error(fmt::format("device {} ({}) cannot run vkpath: {}", *requested,
                                                 infos[*requested].name, why));
        index = *requested;
    } else {
        index = preferredDeviceIndex(infos);
    }
    m_physicalDevice = devices[index];
    m_info = infos[index];
    vkGetPhysicalDeviceMemoryProperties(m_physicalDevice, &m_memory);
}

void Context::createDevice() {
    uint32_t timestampBits = 0;
    const auto family = computeQueueFamily(m_physicalDevice, &timestampBits);
    if (!family)
        throw std::runtime_error(fmt::format("device {} has no compute queue", m_info.name));
    m_queueFamily = *family;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = m_queueFamily;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;

    VkPhysicalDeviceVulkan12Features features12{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    features12.scalarBlockLayout = VK_TRUE;
    features12.bufferDeviceAddress = m_info.bufferDeviceAddress;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features12;
    features.features.shaderInt64 = m_info.shaderInt64;
    features.features.shaderFloat64 = m_info.shaderFloat64;
    // Ray queries where the device has them (--traversal rayquery,
    // host/bvh/acceleration_structures.h).
    VkPhysicalDeviceAccelerationStructureFeaturesKHR structures{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    structures.accelerationStructure = VK_TRUE;
    VkPhysicalDeviceRayQueryFeaturesKHR query{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    query.rayQuery = VK_TRUE;
    std::vector<const char*> extensions;
    if (m_info.rayQuery) {
        extensions = {VK_KHR_RAY_QUERY_EXTENSION_NAME, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                      VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};
        query.pNext = &structures;
        features12.pNext = &query;
    }

    VkDeviceCreateInfo create{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    create.pNext = &features;
    create.queueCreateInfoCount = 1;
    create.pQueueCreateInfos = &queue;
    create.enabledExtensionCount = uint32_t(extensions.size());
    create.ppEnabledExtensionNames = extensions.data();
    VK_CHECK(vkCreateDevice(m_physicalDevice, &create, nullptr, &m_device));
    vkGetDeviceQueue(m_device, m_queueFamily, 0, &m_queue);

    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = m_queueFamily;
    VK_CHECK(vkCreateCommandPool(m_device, &pool, nullptr, &m_commandPool));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VK_CHECK(vkCreateFence(m_device, &fence, nullptr, &m_fence));
}

std::filesystem::path Context::pipelineCacheFile() const {
    const auto dir = pipelineCacheDirectory();
    if (dir.empty()) return {};
    std::string uuid;
    for (uint8_t b : m_info.pipelineCacheUuid) uuid += fmt::format("{:02x}", b);
    return dir /
           fmt::format("pipelines-{:04x}-{:04x}-{}.bin", m_info.vendorId, m_info.deviceId, uuid);
}

void Context::loadPipelineCache() {
    std::vector<char> data;
    const auto file = pipelineCacheFile();
    if (m_usePipelineCache && !file.empty()) {
        std::ifstream in(file, std::ios::binary);
        if (in) data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        // The header (Vulkan spec, vkGetPipelineCacheData): length, version,
        // vendor, device, UUID. A cache of another driver is dropped, not passed on.
        const bool valid =
            data.size() >= 32 && std::memcmp(data.data() + 8, &m_info.vendorId, 4) == 0 &&
            std::memcmp(data.data() + 12, &m_info.deviceId, 4) == 0 &&
            std::memcmp(data.data() + 16, m_info.pipelineCacheUuid.data(), VK_UUID_SIZE) == 0;
        if (!valid) data.clear();
    }
    VkPipelineCacheCreateInfo create{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    create.initialDataSize = data.size();
    create.pInitialData = data.empty() ? nullptr : data.data();
    VK_CHECK(vkCreatePipelineCache(m_device, &create, nullptr, &m_pipelineCache));
}

void Context::savePipelineCache() const {
    const auto file = pipelineCacheFile();
    if (!m_usePipelineCache || file.empty()) return;
    size_t size = 0;
    VK_CHECK(vkGetPipelineCacheData(m_device, m_pipelineCache, &size, nullptr));
    std::vector<char> data(size);
    VK_CHECK(vkGetPipelineCacheData(m_device, m_pipelineCache, &size, data.data()));
    std::filesystem::create_directories(file.parent_path());
    // Write beside and rename, so a concurrent reader never sees half a file.
    const auto temp = file.string() + fmt::format(".{}.tmp", reinterpret_cast<uintptr_t>(this));
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        out.write(data.data(), static_cast<std::streamsize>(size));
        if (!out) throw std::runtime_error(fmt::format("cannot write {}", temp));
    }
    std::filesystem::rename(temp, file);
}

void Context::submit(const std::function<void(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = m_commandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(m_device, &alloc, &cmd));
    struct Free {
        VkDevice device;
        VkCommandPool pool;
        VkCommandBuffer cmd;
        ~Free() { vkFreeCommandBuffers(device, pool, 1, &cmd); }
    } freeOnExit{m_device, m_commandPool, cmd};

    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    record(cmd);
    VK_CHECK(vkEndCommandBuffer(cmd));

    VkSubmitInfo submitInfo{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submitInfo.commandBufferCount = 1;
    submitInfo.pCommandBuffers = &cmd;
    VK_CHECK(vkQueueSubmit(m_queue, 1, &submitInfo, m_fence));
    VK_CHECK(vkWaitForFences(m_device, 1, &m_fence, VK_TRUE, UINT64_MAX));
    VK_CHECK(vkResetFences(m_device, 1, &m_fence));
}

std::optional<uint32_t> Context::tryFindMemoryType(uint32_t typeBits,
                                                   VkMemoryPropertyFlags required) const {
    for (uint32_t i = 0; i < m_memory.memoryTypeCount; ++i) {
        if ((typeBits & (1u << i)) &&
            (m_memory.memoryTypes[i].propertyFlags & required) == required)
            return i;
    }
    return std::nullopt;
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
    if (auto type = tryFindMemoryType(typeBits, required)) return *type;
    throw std::runtime_error(
        fmt::format("no memory type with flags {:#x} among {:#x}", required, typeBits));
}

}  // namespace vkpath::vk
