// converge's pure parts: the --spp list, the knob table behind --sweep, and
// the figures read off a curve (time to reach an error, efficiency).
#include "app/convergence.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "input_error.h"

namespace {

using namespace vkpath;
using app::Checkpoint;

TEST(Convergence, SppListsAreIncreasingCounts) {
    EXPECT_EQ(app::parseSppList("1,2,4,64"), (std::vector<uint32_t>{1, 2, 4, 64}));
    EXPECT_EQ(app::parseSppList("7"), (std::vector<uint32_t>{7}));
    for (const char* bad :
         {"", "1,,2", "4,2", "1,1", "0,1", "1,x", "-1", "1, 2", "2,", "99999999999"})
        EXPECT_THROW(app::parseSppList(bad), InputError) << bad;
}

TEST(Convergence, SweepsNameAKnobAndValuesItAccepts) {
    const app::Sweep sweep = app::parseSweep("max-depth=1,2,16");
    ASSERT_NE(sweep.knob, nullptr);
    EXPECT_STREQ(sweep.knob->name, "max-depth");
    EXPECT_EQ(sweep.values, (std::vector<std::string>{"1", "2", "16"}));
    wavefront::RenderSettings s;
    sweep.knob->apply(s, "16");
    EXPECT_EQ(s.maxDepth, 16u);

    const app::Sweep clamp = app::parseSweep("clamp=off,10");
    clamp.knob->apply(s, "10");
    EXPECT_EQ(s.clampRadiance, 10.0f);
    clamp.knob->apply(s, "off");
    EXPECT_EQ(s.clampRadiance, 0.0f);

    app::parseSweep("light-samples=1,2,4").knob->apply(s, "4");
    EXPECT_EQ(s.lightSamples, 4u);
    app::parseSweep("rr-depth=1,8").knob->apply(s, "8");
    EXPECT_EQ(s.rouletteDepth, 8u);
    app::parseSweep("sampler=independent,sobol").knob->apply(s, "sobol");
    EXPECT_EQ(s.sampler, wavefront::SamplerKind::Sobol);
    app::parseSweep("light-sampler=power,tree").knob->apply(s, "tree");
    EXPECT_EQ(s.lightSampling, wavefront::LightSampling::Tree);

    for (const char* bad :
         {"max-depth", "no-such-knob=1", "max-depth=", "max-depth=1,,2", "max-depth=two", "clamp=0",
          "clamp=-1", "clamp=inf", "rr-depth=1.5", "sampler=halton", "light-sampler=bvh"})
        EXPECT_THROW(app::parseSweep(bad), InputError) << bad;
}

TEST(Convergence, EveryKnobHasAUniqueName) {
    std::set<std::string> names;
    for (const app::Knob& k : app::knobs()) EXPECT_TRUE(names.insert(k.name).second) << k.name;
}

std::vector<Checkpoint> curve(std::initializer_list<std::pair<double, double>> timeAndRelMse) {
    std::vector<Checkpoint> c;
    uint32_t spp = 1;
    for (const auto& [t, e] : timeAndRelMse) {
        Checkpoint p;
        p.spp = spp *= 2;
        p.wallSeconds = t;
        p.relMse = e;
        c.push_back(p);
    }
    return c;
}

TEST(Convergence, TimeToErrorInterpolatesOnLogLogAxes) {
    // relMSE = 0.1 / t: a straight line on log-log axes, so interpolation is exact.
    const auto c = curve({{1, 1e-1}, {10, 1e-2}, {100, 1e-3}});
    EXPECT_NEAR(*app::timeToRelMse(c, 1e-2), 10, 1e-9);
    EXPECT_NEAR(*app::timeToRelMse(c, std::sqrt(1e-1 * 1e-2)), std::sqrt(10.0), 1e-9);
    EXPECT_NEAR(*app::timeToRelMse(c, 2e-3), 50, 1e-9);
    // Reached at the first checkpoint: its time; never reached: nothing.
    EXPECT_EQ(*app::timeToRelMse(c, 1), 1);
    EXPECT_FALSE(app::timeToRelMse(c, 1e-4));
    EXPECT_FALSE(app::timeToRelMse({}, 1));
}

TEST(Convergence, TimeToErrorTakesTheFirstCrossingOfANoisyCurve) {
    // Noise can push the error back up after a crossing: the first one counts.
    const auto c = curve({{1, 4e-2}, {2, 1e-2}, {4, 1.5e-2}, {8, 5e-3}});
    EXPECT_NEAR(*app::timeToRelMse(c, 2e-2), 1 * std::pow(2.0, 0.5), 1e-9);
}

TEST(Convergence, EfficiencyIsInverseTimeTimesError) {
    EXPECT_DOUBLE_EQ(app::efficiency(curve({{1, 1}, {2, 0.05}})), 10);
    EXPECT_EQ(app::efficiency({}), 0);
    EXPECT_TRUE(std::isinf(app::efficiency(curve({{2, 0}}))));
}

}  // namespace
