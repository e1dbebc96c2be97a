// vk::decorateNoContraction (host/vk/spirv_no_contraction.h) on every stage
// kernel, checked by SPIRV-Tools (glslang-tools depends on it): spirv-val
// accepts the module it makes, and in spirv-dis's listing every float
// multiply, add, division and dot product carries NoContraction exactly once.
// lavapipe fuses nothing either way; on NVIDIA's driver this is what keeps the
// kernel forms bit for bit alike (AllScenes.EveryKernelGivesTheSameImage).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <span>
#include <sstream>
#include <string>

#include "support/temp_dir.h"
#include "vk/embedded_shaders.h"
#include "vk/spirv_no_contraction.h"

namespace {

using namespace vkpath;

std::string run(const std::string& command) {
    std::string out;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return "popen failed";
    char buffer[4096];
    while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
    const int status = pclose(pipe);
    if (status != 0) out += "\nexit status " + std::to_string(status);
    return out;
}

std::filesystem::path writeModule(const test::TempDir& dir, const std::string& name,
                                  const std::vector<uint32_t>& words) {
    return dir.write(name + ".spv",
                     std::string(reinterpret_cast<const char*>(words.data()), words.size() * 4));
}

struct Listing {
    std::vector<std::string>
        arithmetic;  // result ids of float multiplies, adds, divisions, dot products
    std::map<std::string, int> decorations;  // NoContraction decorations per id
};

Listing disassemble(const std::filesystem::path& file) {
    const std::regex arithmetic(
        R"(^\s*(%\S+) = Op(FAdd|FSub|FMul|FDiv|Dot|VectorTimesScalar|MatrixTimes\w+|OuterProduct) )");
    const std::regex decoration(R"(^\s*OpDecorate (%\S+) NoContraction\s*$)");
    Listing listing;
    std::istringstream text(run("spirv-dis --raw-id " + file.string()));
    std::smatch m;
    for (std::string line; std::getline(text, line);) {
        if (std::regex_search(line, m, decoration))
            ++listing.decorations[m[1]];
        else if (std::regex_search(line, m, arithmetic))
            listing.arithmetic.push_back(m[1]);
    }
    return listing;
}

TEST(NoContraction, EveryFloatArithmeticResultOfEveryStageKernelIsDecoratedOnce) {
    const test::TempDir dir;
    ASSERT_FALSE(shaders::stageKernels().empty());
    size_t total = 0;
    for (const shaders::EmbeddedShader& kernel : shaders::stageKernels()) {
        SCOPED_TRACE(kernel.name);
        const std::vector<uint32_t> decorated = vk::decorateNoContraction(kernel.spirv);
        const std::filesystem::path file = writeModule(dir, kernel.name, decorated);
        EXPECT_EQ(run("spirv-val --target-env vulkan1.2 --scalar-block-layout " + file.string()),
                  "");

        const Listing before = disassemble(
            writeModule(dir, std::string(kernel.name) + "-before",
                        std::vector<uint32_t>(kernel.spirv.begin(), kernel.spirv.end())));
        const Listing after = disassemble(file);
        EXPECT_EQ(after.arithmetic, before.arithmetic);
        total += after.arithmetic.size();
        std::map<std::string, int> expected = before.decorations;  // glslang's, from `precise`
        for (const std::string& id : after.arithmetic) expected[id] = 1;
        EXPECT_EQ(after.decorations, expected);

        // Applying it again changes nothing.
        EXPECT_EQ(vk::decorateNoContraction(decorated), decorated);
    }
    EXPECT_GT(total, 1000u) << "spirv-dis listed too few float operations to mean much";
}

TEST(NoContraction, RejectsWhatIsNotSpirv) {
    const std::vector<uint32_t> notSpirv{1, 2, 3, 4, 5, 6};
    EXPECT_THROW(vk::decorateNoContraction(notSpirv), std::runtime_error);
    const std::span<const uint32_t> generate = shaders::findKernel("generate");
    std::vector<uint32_t> truncated(generate.begin(), generate.end());
    truncated.push_back((4u << 16) | 129);  // an OpFAdd of four words, with one left
    EXPECT_THROW(vk::decorateNoContraction(truncated), std::runtime_error);
}

}  // namespace
