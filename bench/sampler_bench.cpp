// The samplers' cost on the CPU (Google Benchmark): nanoseconds per pair of
// numbers from rngBits2 (shared/rng.h), Sobol' and independent, over keys of
// many pixels and sample indices, as the CPU reference draws them; and per
// bit reversal, shared::bitfieldReverse (GFNI where the machine has it,
// shared/compat.h) against GLM's. Figures: docs/BENCHMARKS.md.
//
//   build/sampler_bench [benchmark flags]
#include <benchmark/benchmark.h>

#include <cstdint>

#include "shared/rng.h"

namespace {

using namespace vkpath;

// Pairs of one path's dimensions for consecutive paths: each iteration is
// independent of the last, so this measures throughput, as a path's many
// draws between its other work do.
void pairs(benchmark::State& state, uint32_t samplerKind) {
    uint32_t path = 0;
    for (auto _ : state) {
        const shared::RngKey key = shared::makeRngKey(path * 7919u, path & 1023u, 3u, samplerKind);
        glm::uvec2 bits = shared::rngBits2(key, 2u + 2u * (path % 8u));
        benchmark::DoNotOptimize(bits);
        ++path;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_SobolPair(benchmark::State& state) {
    pairs(state, VKP_SAMPLER_SOBOL);
}
void BM_IndependentPair(benchmark::State& state) {
    pairs(state, VKP_SAMPLER_INDEPENDENT);
}

// Reversals in a chain, each of the last one's result, as the Sobol'
// sampler's are (reverse, hash, reverse): latency, which no compiler can
// spread over vector lanes as it can a loop over an array.
template <uint32_t (*Reverse)(uint32_t)>
void reversals(benchmark::State& state) {
    uint32_t x = 0x12345678u;
    for (auto _ : state) {
        for (uint32_t i = 0; i < 64u; ++i) x = Reverse(x) + i;
        benchmark::DoNotOptimize(x);
    }
    state.SetItemsProcessed(state.iterations() * 64);
}

uint32_t sharedReverse(uint32_t x) {
    return shared::bitfieldReverse(x);
}
uint32_t glmReverse(uint32_t x) {
    return glm::bitfieldReverse(x);
}

void BM_BitReverseShared(benchmark::State& state) {
    reversals<sharedReverse>(state);
}
void BM_BitReverseGlm(benchmark::State& state) {
    reversals<glmReverse>(state);
}

BENCHMARK(BM_SobolPair);
BENCHMARK(BM_IndependentPair);
BENCHMARK(BM_BitReverseShared);
BENCHMARK(BM_BitReverseGlm);

}  // namespace

BENCHMARK_MAIN();
