// The chi-square machinery itself, against values from standard tables.
#include "support/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

using namespace vkpath::test;

TEST(Statistics, ChiSquarePValueMatchesTables) {
    // Chi-square upper-tail probabilities: Q(k/2, x/2).
    EXPECT_NEAR(chiSquarePValue(3.841458820694124, 1), 0.05, 1e-9);    // k = 1
    EXPECT_NEAR(chiSquarePValue(23.209251158954356, 10), 0.01, 1e-9);  // k = 10
    EXPECT_NEAR(chiSquarePValue(82.52872654, 63), 0.05, 1e-6);         // k = 63
    EXPECT_NEAR(chiSquarePValue(4.0, 2), std::exp(-2.0), 1e-12);       // k = 2: Q(1, x) = e^-x
}

TEST(Statistics, ChiSquarePoolsAndRejects) {
    // A perfect fit has statistic 0 and p = 1.
    auto fit = chiSquareTest({10, 20, 30}, {10, 20, 30});
    EXPECT_EQ(fit.statistic, 0.0);
    EXPECT_EQ(fit.degreesOfFreedom, 2);
    EXPECT_NEAR(fit.pValue, 1.0, 1e-12);
    // Cells with expected < 5 are pooled: {2, 1} becomes one cell.
    auto pooled = chiSquareTest({10, 2, 1}, {10, 1.5, 1.5});
    EXPECT_EQ(pooled.pooledCells, 2u);
    EXPECT_EQ(pooled.degreesOfFreedom, 1);
    // Samples in a cell of zero expectation fail outright.
    auto impossible = chiSquareTest({10, 1}, {11, 0});
    EXPECT_EQ(impossible.pValue, 0.0);
    // A grossly wrong distribution is rejected.
    EXPECT_LT(chiSquareTest({100, 0}, {50, 50}).pValue, 1e-10);
}

TEST(Statistics, Sidak) {
    EXPECT_NEAR(sidakAlpha(0.01, 1), 0.01, 1e-15);
    EXPECT_LT(sidakAlpha(0.01, 10), 0.001006);
}

}  // namespace

#include "shared/precise_math.h"

namespace {

// The shared inverse trigonometry against the C library in double. Results
// reach pi, where one float ulp is 2.4e-7: the bound is 1.5 ulp there.
TEST(PreciseMath, AtanAndAcosWithinOneAndAHalfUlpOfPi) {
    double worst = 0;
    for (int i = -1000; i <= 1000; ++i)
        for (int j = -1000; j <= 1000; j += 7) {
            const float y = i * 0.013f, x = j * 0.011f;
            if (x == 0 && y == 0) continue;
            worst = std::max(worst, std::abs(vkpath::shared::preciseAtan2(y, x) -
                                             std::atan2(double(y), double(x))));
        }
    EXPECT_LT(worst, 3.6e-7);
    worst = 0;
    for (int i = -100000; i <= 100000; ++i) {
        const float c = i * 1e-5f;
        worst = std::max(worst, std::abs(vkpath::shared::preciseAcos(c) - std::acos(double(c))));
    }
    EXPECT_LT(worst, 3.6e-7);
    EXPECT_EQ(vkpath::shared::preciseAtan2(0.0f, 0.0f), 0.0f);
}

}  // namespace

#include "scene/alias_table.h"
#include "shared/alias.h"

namespace {

// The alias table's probabilities are exact for its own thresholds: counting
// every (bucket, bits) outcome class gives them back, and tiny weights keep
// a nonzero share.
TEST(AliasTable, ProbabilitiesMatchWeightsAndSurviveTinyWeights) {
    const std::vector<double> weights = {1e-12, 3.0, 0.0, 1.0, 1e7, -2.0, std::nan("")};
    const auto table = vkpath::scene::buildAliasTable(weights);
    ASSERT_EQ(table.size(), weights.size());
    const double total = 1e-12 + 3.0 + 1.0 + 1e7;
    for (size_t i = 0; i < weights.size(); ++i) {
        const double expected =
            std::isfinite(weights[i]) && weights[i] > 0 ? weights[i] / total : 0.0;
        if (expected == 0) {
            EXPECT_EQ(table[i].probability, 0.0f) << i;
        } else {
            EXPECT_GT(table[i].probability, 0.0f) << i;
            // Quantisation: one part in 2^32 of a bucket, relative to N / 2^32.
            EXPECT_NEAR(table[i].probability, expected,
                        std::max(expected * 1e-6, 7.0 / 4294967296.0))
                << i;
        }
    }
    // Resolving extreme random words stays in range.
    for (uint32_t bits : {0u, 0x7fffffffu, 0xffffffffu}) {
        const uint32_t bucket = vkpath::shared::aliasBucket(bits, uint32_t(table.size()));
        ASSERT_LT(bucket, table.size());
        const uint32_t element = vkpath::shared::aliasResolve(table[bucket], bucket, bits);
        ASSERT_LT(element, table.size());
        EXPECT_GT(table[element].probability, 0.0f);
    }
    EXPECT_TRUE(vkpath::scene::buildAliasTable(std::vector<double>{0.0, -1.0}).empty());
}

}  // namespace

namespace {

// One word chooses the element and, rescaled, gives a number in [0, 1) that is
// uniform within each element's share (shared/alias.h aliasSampleReusing), so a
// stratified set of words stays stratified over every element. Words at the
// centres of N equal cells: each element's part of a bucket is an interval of
// words, rescaled linearly to [0, 1), so its numbers are evenly spaced over
// [0, 1) within each part; with P parts an element's empirical CDF is within
// P / n of the uniform one (n its count), and its count within P of p N.
TEST(AliasTable, ReusedWordIsUniformWithinEachElementAndKeepsStratification) {
    using vkpath::shared::aliasBucket;
    using vkpath::shared::aliasBucketFraction;
    using vkpath::shared::aliasSampleReusing;
    const std::vector<double> weights = {1.0, 3.0, 0.5, 2.5, 0.0, 1.0};
    const auto table = vkpath::scene::buildAliasTable(weights);
    const auto count = uint32_t(table.size());
    const uint32_t n = 1u << 16;
    std::vector<std::vector<float>> numbers(count);
    for (uint32_t i = 0; i < n; ++i) {
        const auto word = uint32_t(((uint64_t(i) << 32) + (uint64_t(1) << 31)) / n);
        const uint32_t bucket = aliasBucket(word, count);
        const auto choice =
            aliasSampleReusing(table[bucket], bucket, aliasBucketFraction(word, count));
        ASSERT_LT(choice.element, count);
        ASSERT_GE(choice.u, 0.0f);
        ASSERT_LT(choice.u, 1.0f);
        numbers[choice.element].push_back(choice.u);
    }
    for (uint32_t e = 0; e < count; ++e) {
        // Its parts: its own bucket's kept part and the rest of every bucket aliasing it.
        double parts = table[e].threshold > 0 ? 1 : 0;
        for (uint32_t b = 0; b < count; ++b)
            parts += table[b].alias == e && table[b].threshold != 0xffffffffu;
        auto& u = numbers[e];
        EXPECT_NEAR(double(u.size()), double(table[e].probability) * n, parts + 1) << e;
        if (u.empty()) continue;
        std::sort(u.begin(), u.end());
        double worst = 0;
        for (size_t k = 0; k < u.size(); ++k)
            worst = std::max({worst, std::abs(double(u[k]) - double(k) / u.size()),
                              std::abs(double(u[k]) - double(k + 1) / u.size())});
        EXPECT_LE(worst, (parts + 1) / double(u.size())) << e;
    }
    EXPECT_TRUE(numbers[4].empty());  // weight 0

    // Two equal elements: each gets one number in every cell of width 2 / n.
    const auto halves = vkpath::scene::buildAliasTable(std::vector<double>{1.0, 1.0});
    std::vector<std::vector<int>> cells(2, std::vector<int>(n / 2, 0));
    for (uint32_t i = 0; i < n; ++i) {
        const auto word = uint32_t(((uint64_t(i) << 32) + (uint64_t(1) << 31)) / n);
        const uint32_t bucket = aliasBucket(word, 2);
        const auto choice =
            aliasSampleReusing(halves[bucket], bucket, aliasBucketFraction(word, 2));
        ++cells[choice.element][size_t(double(choice.u) * (n / 2))];
    }
    for (const auto& element : cells)
        EXPECT_EQ(std::count(element.begin(), element.end(), 1), std::ptrdiff_t(n / 2));

    // An element of tiny probability owns a sliver of words: its rescaled
    // fraction would take few values, so it is marked not reusable, and
    // elements with room are.
    const auto tiny = vkpath::scene::buildAliasTable(std::vector<double>{1e-9, 1.0});
    for (uint32_t word : {0u, 1u, 100u, 0x40000000u, 0x80000000u, 0xc0000000u}) {
        const uint32_t bucket = aliasBucket(word, 2);
        const auto choice = aliasSampleReusing(tiny[bucket], bucket, aliasBucketFraction(word, 2));
        EXPECT_EQ(choice.reusable, choice.element == 1) << word;
    }
    EXPECT_EQ(aliasSampleReusing(tiny[0], 0, 0u).element, 0u);

    // The extreme words stay in [0, 1), also in a bucket kept whole.
    for (uint32_t word : {0u, 1u, 0x7fffffffu, 0x80000000u, 0xfffffffeu, 0xffffffffu})
        for (const auto& t : {table, halves}) {
            const auto c = uint32_t(t.size());
            const uint32_t bucket = aliasBucket(word, c);
            const auto choice = aliasSampleReusing(t[bucket], bucket, aliasBucketFraction(word, c));
            EXPECT_GE(choice.u, 0.0f);
            EXPECT_LT(choice.u, 1.0f);
            EXPECT_GT(t[choice.element].probability, 0.0f);
        }
}

}  // namespace
