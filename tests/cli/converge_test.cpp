// `vkpath converge` as a user runs it: on a 32x24 film of the bundled diffuse
// Cornell box, the error it records falls with the sample count, on either
// device, against a reference or estimated from a second seed; the plot is
// written; a sweep records one curve per value; bad input is refused.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "image/image.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;

struct Row {
    std::string knob, value;
    uint32_t spp = 0;
    double wallSeconds = 0;
    std::string deviceSeconds;
    double relMse = 0, rmse = 0, relMseTrimmed = 0;
    std::string error;
    double estimatedRelMse = 0;
};

std::vector<Row> readCsv(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line,
              "knob,value,spp,wall_seconds,device_seconds,relmse,rmse,relmse_trimmed,error,"
              "estimated_relmse");
    std::vector<Row> rows;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream s(line);
        for (std::string field; std::getline(s, field, ',');) f.push_back(field);
        EXPECT_EQ(f.size(), 10u) << line;
        if (f.size() != 10) continue;
        rows.push_back({f[0], f[1], uint32_t(std::stoul(f[2])), std::stod(f[3]), f[4],
                        std::stod(f[5]), std::stod(f[6]), std::stod(f[7]), f[8], std::stod(f[9])});
    }
    return rows;
}

std::string scene() {
    return test::sourcePath("assets/cornell_box_diffuse.gltf").string();
}

// From 1 to 64 spp relMSE should fall 64x and RMSE 8x. Measured over seeds
// 0-9 on this 32x24 film (1536 channel values, heavy-tailed: a firefly can
// lift one checkpoint 20x), the fall was at least 8.6x for relMSE and 2.7x
// for RMSE, against the reference and by the two-seed estimate alike,
// and the 64-spp error was always the lowest, at least 1.5x below every
// earlier one. The bounds below sit about half-way under the worst of those
// twenty runs: a renderer whose error stalls fails them, noise does not.
constexpr double MIN_RELMSE_FALL = 4;
constexpr double MIN_RMSE_FALL = 1.6;

void expectFallingError(const std::vector<Row>& rows, const std::string& device) {
    ASSERT_EQ(rows.size(), 4u);
    for (size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(rows[i].spp, std::vector<uint32_t>({1, 4, 16, 64})[i]);
        EXPECT_GT(rows[i].relMse, 0);
        EXPECT_GT(rows[i].wallSeconds, 0);
        if (i > 0) {
            EXPECT_GE(rows[i].wallSeconds, rows[i - 1].wallSeconds);
        }
        if (i + 1 < rows.size()) {
            EXPECT_LT(rows.back().relMse, rows[i].relMse) << "spp " << rows[i].spp;
        }
        // Device time is the GPU's; the CPU reference has none.
        EXPECT_EQ(rows[i].deviceSeconds.empty(), device == "cpu");
    }
    EXPECT_LT(rows.back().relMse * MIN_RELMSE_FALL, rows.front().relMse);
    EXPECT_LT(rows.back().rmse * MIN_RMSE_FALL, rows.front().rmse);
}

class ConvergeDevice : public testing::TestWithParam<std::string> {};

TEST_P(ConvergeDevice, ErrorAgainstAReferenceFallsWithSamples) {
    const test::TempDir dir;
    const auto ref = dir / "ref.exr";
    // 1024 spp: its own relMSE is 1/16 of the 64-spp render's, small beside the margin.
    ASSERT_EQ(test::runVkpath(fmt::format("render {} -d 32x24 --device cpu -s 1024 --seed 99 -o {}",
                                          scene(), ref.string()))
                  .exitCode,
              0);
    const auto r = test::runVkpath(fmt::format(
        "converge {} -d 32x24 --device {} --spp 1,4,16,64 --reference {} --csv {} --plot {}",
        scene(), GetParam(), ref.string(), (dir / "c.csv").string(), (dir / "c.png").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto rows = readCsv(dir / "c.csv");
    expectFallingError(rows, GetParam());
    for (const Row& row : rows) EXPECT_EQ(row.error, "reference");
    const image::Image plot = image::readImage(dir / "c.png");
    EXPECT_EQ(plot.width, 1000u);
    EXPECT_EQ(plot.height, 600u);
    EXPECT_NE(r.out.find("time to reach relMSE"), std::string::npos) << r.out;
}

TEST_P(ConvergeDevice, ErrorEstimatedFromASecondSeedFallsWithSamples) {
    const test::TempDir dir;
    const auto r = test::runVkpath(
        fmt::format("converge {} -d 32x24 --device {} --spp 1,4,16,64 --csv {} --plot {}", scene(),
                    GetParam(), (dir / "c.csv").string(), (dir / "c.png").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto rows = readCsv(dir / "c.csv");
    expectFallingError(rows, GetParam());
    for (const Row& row : rows) EXPECT_EQ(row.error, "two-seed estimate");
    EXPECT_TRUE(std::filesystem::is_regular_file(dir / "c.png"));
}

INSTANTIATE_TEST_SUITE_P(Devices, ConvergeDevice, testing::Values("gpu", "cpu"));

TEST(Converge, SweepRecordsOneCurvePerValue) {
    const test::TempDir dir;
    const auto r = test::runVkpath(
        fmt::format("converge {} -d 16x12 --spp 1,4 --sweep max-depth=0,1,4 --csv {} --plot {}",
                    scene(), (dir / "c.csv").string(), (dir / "c.png").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::map<std::string, std::vector<uint32_t>> curves;
    for (const Row& row : readCsv(dir / "c.csv")) {
        EXPECT_EQ(row.knob, "max-depth");
        curves[row.value].push_back(row.spp);
    }
    const std::vector<uint32_t> spp = {1, 4};
    EXPECT_EQ(curves,
              (std::map<std::string, std::vector<uint32_t>>{{"0", spp}, {"1", spp}, {"4", spp}}));
    EXPECT_NE(r.out.find("<- best"), std::string::npos) << r.out;
}

// Every knob of the table runs, one curve per value; sweeping a biased knob
// (clamp, max-depth) without a reference warns that the two-seed estimate
// cannot see its bias, an unbiased one does not.
struct KnobCase {
    const char* sweep;
    std::vector<std::string> values;
    bool warns;
};

void PrintTo(const KnobCase& k, std::ostream* os) {
    *os << k.sweep;
}

class ConvergeKnob : public testing::TestWithParam<KnobCase> {};

TEST_P(ConvergeKnob, SweepRunsEveryValue) {
    const KnobCase& k = GetParam();
    const test::TempDir dir;
    // Outputs in the test's own folder: parallel tests must not share out/converge.png.
    const auto r = test::runVkpath(
        fmt::format("converge {} -d 16x12 --device cpu --spp 1,2 --sweep {} --csv {} --plot {}",
                    scene(), k.sweep, (dir / "c.csv").string(), (dir / "c.png").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::map<std::string, size_t> points;
    for (const Row& row : readCsv(dir / "c.csv")) points[row.value] += 1;
    std::map<std::string, size_t> expected;
    for (const std::string& v : k.values) expected[v] = 2;
    EXPECT_EQ(points, expected);
    EXPECT_EQ(r.err.find("warning: --sweep") != std::string::npos, k.warns) << r.err;
}

// --metric trimmed-relmse: the tables and the plot use the trimmed relMSE,
// which the CSV records beside the plain one, never above it.
TEST(Converge, TrimmedMetricDrivesTheTables) {
    const test::TempDir dir;
    const auto r = test::runVkpath(
        fmt::format("converge {} -d 32x24 --device cpu --spp 1,4 --metric trimmed-relmse --csv {} "
                    "--plot {}",
                    scene(), (dir / "c.csv").string(), (dir / "c.png").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("time to reach trimmed relMSE"), std::string::npos) << r.out;
    for (const Row& row : readCsv(dir / "c.csv")) {
        EXPECT_GT(row.relMseTrimmed, 0);
        EXPECT_LE(row.relMseTrimmed, row.relMse);
    }
    EXPECT_EQ(test::runVkpath(fmt::format("converge {} -d 8x8 --metric median", scene())).exitCode,
              2);
}

INSTANTIATE_TEST_SUITE_P(
    Knobs, ConvergeKnob,
    testing::Values(KnobCase{"light-samples=1,2", {"1", "2"}, false},
                    KnobCase{"rr-depth=1,4", {"1", "4"}, false},
                    KnobCase{"sampler=independent,sobol", {"independent", "sobol"}, false},
                    KnobCase{"clamp=off,1", {"off", "1"}, true},
                    KnobCase{"max-depth=1,3", {"1", "3"}, true}),
    [](const testing::TestParamInfo<KnobCase>& p) {
        std::string name = p.param.sweep;
        name = name.substr(0, name.find('='));
        name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
        return name;
    });

TEST(Converge, BadInputIsOneLineAndExitTwo) {
    const test::TempDir dir;
    const auto ref = dir / "ref.exr";
    ASSERT_EQ(test::runVkpath(
                  fmt::format("render {} -d 8x6 --device cpu -s 1 -o {}", scene(), ref.string()))
                  .exitCode,
              0);
    const auto csv = dir / "c.csv";
    for (const std::string& flags :
         {std::string("--spp 4,2"), std::string("--spp 1,x"), std::string("--spp 0,1"),
          std::string("--sweep no-such-knob=1,2"), std::string("--sweep clamp=-3"),
          "--reference " + ref.string()}) {
        SCOPED_TRACE(flags);
        const auto r =
            test::runVkpath(fmt::format("converge {} -d 16x12 {} --csv {} --plot {}", scene(),
                                        flags, csv.string(), (dir / "c.png").string()));
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
        EXPECT_FALSE(std::filesystem::exists(csv));
    }
}

// --target-error ends the curve at the first checkpoint from 16 spp on (as
// render's stop: fewer samples' variance is too rough, at 1 spp none) whose
// own estimate reaches it; --adaptive is refused (converge renders uniform
// sample ranges).
TEST(Converge, TargetErrorEndsTheCurve) {
    const test::TempDir dir;
    const std::string csv = (dir / "c.csv").string();
    const auto r = test::runVkpath("converge " + scene() +
                                   " -d 32x24 --spp 1,2,4,8,16,32,64 --target-error 0.05 --csv " +
                                   csv + " --plot " + (dir / "c.png").string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::vector<Row> rows = readCsv(csv);
    ASSERT_FALSE(rows.empty());
    EXPECT_LT(rows.size(), 7u) << "the curve did not stop";
    EXPECT_LE(rows.back().estimatedRelMse, 0.05);
    EXPECT_GE(rows.back().spp, 16u);
    for (size_t i = 0; i + 1 < rows.size(); ++i) {
        if (rows[i].spp >= 16) {
            EXPECT_GT(rows[i].estimatedRelMse, 0.05);
        }
    }

    const auto refused = test::runVkpath("converge " + scene() + " -d 8x8 --adaptive --csv " + csv);
    EXPECT_EQ(refused.exitCode, 2);
    EXPECT_EQ(test::lineCount(refused.err), 1) << refused.err;
}

}  // namespace
