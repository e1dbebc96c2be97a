// Writes the albedo tables of shaders/shared/microfacet_albedo.h
// as a C++ initialiser list, one float per entry in the table's order, for
// host/albedo/albedo_tables.cpp to include. Run by the build
// (host/CMakeLists.txt), so the tables always match the lobes they describe:
//
//   make_albedo_tables OUTPUT
//
// Every entry is albedo_integrals.h's integral at its grid point; the
// entries are independent, so the hardware's threads share them.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <thread>
#include <vector>

#include "albedo/albedo_integrals.h"
#include "shared/microfacet_albedo.h"

namespace {

using namespace vkpath;

// The table entry at `index` (shared/microfacet_albedo.h's layout).
float entry(uint32_t index) {
    const uint32_t cosIndex = index % VKP_ALBEDO_COS_COUNT;
    const uint32_t roughnessIndex = index / VKP_ALBEDO_COS_COUNT % VKP_ALBEDO_ROUGHNESS_COUNT;
    const float cosTheta = shared::albedoGridCos(cosIndex);
    const float roughness = shared::albedoGridRoughness(roughnessIndex);
    if (index < VKP_ALBEDO_ENTERING_OFFSET)
        return float(albedo::conductorAlbedo(cosTheta, roughness));
    if (index >= VKP_ALBEDO_SHEEN_OFFSET) return float(albedo::sheenAlbedo(cosTheta, roughness));
    const bool leaving = index >= VKP_ALBEDO_LEAVING_OFFSET;
    const uint32_t glassIndex =
        index - (leaving ? VKP_ALBEDO_LEAVING_OFFSET : VKP_ALBEDO_ENTERING_OFFSET);
    const float eta = shared::albedoGridIor(glassIndex / VKP_ALBEDO_CONDUCTOR_SIZE);
    return float(albedo::dielectricAlbedo(cosTheta, roughness, leaving ? 1.0f / eta : eta));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_albedo_tables OUTPUT\n");
        return 2;
    }
    std::vector<float> table(VKP_ALBEDO_TABLE_SIZE);
    std::atomic<uint32_t> next{0};
    std::vector<std::thread> workers;
    for (unsigned t = 0; t < std::max(1u, std::thread::hardware_concurrency()); ++t)
        workers.emplace_back([&] {
            for (uint32_t i; (i = next.fetch_add(1)) < table.size();) table[i] = entry(i);
        });
    for (std::thread& worker : workers) worker.join();

    std::FILE* out = std::fopen(argv[1], "w");
    if (!out) {
        std::fprintf(stderr, "%s: cannot write\n", argv[1]);
        return 1;
    }
    std::fprintf(out, "// Written by host/albedo/make_albedo_tables.cpp at build time.\n");
    for (size_t i = 0; i < table.size(); ++i)
        std::fprintf(out, "%af,%s", double(table[i]), i % 8 == 7 ? "\n" : " ");
    std::fprintf(out, "\n");
    return std::fclose(out) == 0 ? 0 : 1;
}
