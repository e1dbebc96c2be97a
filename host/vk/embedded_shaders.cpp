#include "vk/embedded_shaders.h"

#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace vkpath::shaders {
namespace {

struct Registry {
    std::mutex mutex;
    std::vector<std::span<const EmbeddedShader>> groups{stageKernels()};
};

Registry& registry() {
    static Registry r;
    return r;
}

}  // namespace

void registerKernels(std::span<const EmbeddedShader> kernels) {
    std::lock_guard lock(registry().mutex);
    registry().groups.push_back(kernels);
}

std::span<const uint32_t> findKernel(std::string_view name) {
    std::lock_guard lock(registry().mutex);
    for (const auto& group : registry().groups)
        for (const EmbeddedShader& shader : group)
            if (name == shader.name) return shader.spirv;
    throw std::out_of_range("unknown kernel '" + std::string(name) + "'");
}

}  // namespace vkpath::shaders
