#include <gtest/gtest.h>

#include <span>

#include "vk/embedded_shaders.h"

namespace vkpath::shaders {
std::span<const EmbeddedShader> testKernels();
}

int main(int argc, char** argv) {
    testing::InitGoogleTest(&argc, argv);
    vkpath::shaders::registerKernels(vkpath::shaders::testKernels());
    return RUN_ALL_TESTS();
}
