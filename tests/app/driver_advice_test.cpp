// `vkpath info` tells a user whose lavapipe is the slow one what to install.
#include <gtest/gtest.h>

#include "vk/context.h"

namespace {

using namespace vkpath;

vk::DeviceInfo device(const std::string& driverName, const std::string& driverInfo) {
    vk::DeviceInfo d;
    d.driverName = driverName;
    d.driverInfo = driverInfo;
    return d;
}

TEST(DriverAdvice, NamesTheSlowLavapipeAndWhereTheFastOneIs) {
    const std::string advice = vk::driverAdvice(device("llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)"));
    EXPECT_NE(advice.find("Mesa 22.3.6"), std::string::npos) << advice;
    EXPECT_NE(advice.find("bookworm-backports"), std::string::npos) << advice;
}

TEST(DriverAdvice, SaysNothingOfFastOrOtherDrivers) {
    EXPECT_EQ(vk::driverAdvice(device("llvmpipe", "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)")), "");
    EXPECT_EQ(vk::driverAdvice(device("llvmpipe", "Mesa 26.1.0")), "");
    EXPECT_EQ(vk::driverAdvice(device("NVIDIA", "570.86.16")), "");
    EXPECT_EQ(vk::driverAdvice(device("llvmpipe", "")), "");
}

}  // namespace
