// `vkpath render` as a user meets it: Scotty3D's -w, the EXR's metadata, the
// PNG preview and its exposure, the summary line and the progress bar,
// bit-identical reruns, --time-budget, waves made smaller by --max-wave-ms
// and --max-device-memory, the CPU reference's builds, --single-scattering and --variant.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "image/image.h"
#include "support/exr_metadata.h"
#include "support/gltf_builder.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"
#include "support/vdb_grid.h"

namespace {

using namespace vkpath;
using test::vkpathMetadata;

std::string cornellBox() {
    return test::sourcePath("assets/cornell_box.gltf").string();
}

// `render` of the bundled box with `flags` (8 x 8) is refused in one line,
// exit code 2, with nothing written.
void expectRefusedInOneLine(const test::TempDir& dir, const std::string& flags) {
    SCOPED_TRACE(flags);
    const std::string exr = (dir / "x.exr").string();
    const auto r = test::runVkpath("render " + cornellBox() + " -d 8x8 " + flags + " -o " + exr);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(exr));
}

// The file's pixels as stored (float32 EXR, uint8 PNG), byte for byte.
std::vector<unsigned char> storedPixels(const std::string& path, OIIO::TypeDesc type) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<unsigned char> bytes(size_t(spec.width) * spec.height * spec.nchannels *
                                     type.size());
    if (!in->read_image(0, 0, 0, spec.nchannels, type, bytes.data())) return {};
    return bytes;
}

// The summary line's "N NaN/Inf samples dropped" and "at S spp".
struct Summary {
    bool found = false;
    uint32_t spp = 0;
    uint64_t nonFinite = 0;
    double mpaths = 0, mrays = 0;
};
Summary parseSummary(const std::string& err) {
    static const std::regex line(
        R"(rendered \d+x\d+ at (\d+) spp in [0-9.]+ s[^:]*: ([0-9.]+) Mpaths/s \([0-9.]+ per CPU second\), ([0-9.]+) Mrays/s .* (\d+) NaN/Inf samples dropped)");
    std::smatch m;
    Summary s;
    if (!std::regex_search(err, m, line)) return s;
    s.found = true;
    s.spp = uint32_t(std::stoul(m[1]));
    s.mpaths = std::stod(m[2]);
    s.mrays = std::stod(m[3]);
    s.nonFinite = std::stoull(m[4]);
    return s;
}

TEST(RenderCli, ScottyOutputFlagMetadataAndSummary) {
    const test::TempDir dir;
    const std::string exr = (dir / "box.exr").string();
    const auto r =
        test::runVkpath("render " + cornellBox() + " -d 20x16 -s 3 -m 5 -l 2 --seed 11 -w " + exr);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(exr), std::string::npos) << "the written file is named on stdout";
    auto m = vkpathMetadata(exr);
    EXPECT_EQ(m["vkpath:spp"], "3");
    EXPECT_EQ(m["vkpath:seed"], "11");
    EXPECT_EQ(m["vkpath:maxDepth"], "5");
    EXPECT_EQ(m["vkpath:lightSamples"], "2");
    EXPECT_EQ(m["vkpath:sampler"], "sobol") << "the default sampler";
    EXPECT_EQ(m["vkpath:version"], VKPATH_VERSION);
    EXPECT_EQ(m["vkpath:nonFiniteSamples"], "0");
    EXPECT_EQ(m["vkpath:clamp"], "off");
    EXPECT_EQ(m["vkpath:guideSpheres"], "0.25") << "the default";
    EXPECT_FALSE(m["vkpath:device"].empty());
    EXPECT_NE(r.err.find(m["vkpath:device"]), std::string::npos)
        << "the summary names the device the EXR records";
    EXPECT_GT(std::stod(m["vkpath:renderSeconds"]), 0.0);
    const Summary s = parseSummary(r.err);
    ASSERT_TRUE(s.found) << r.err;
    EXPECT_EQ(s.spp, 3u);
    EXPECT_EQ(s.nonFinite, 0u);
    EXPECT_GT(s.mpaths, 0.0);
    EXPECT_GE(s.mrays, s.mpaths) << "at least one closest-hit ray per path";
}

// Multiple-scattering compensation is the default and --single-scattering
// turns it off, on both devices: recorded in the EXR, and the rough spheres
// of material_spheres.gltf (metal and glass up to roughness 1) are brighter
// with it: the image's mean at least 2% above the single-scattering one's
// (measured 3.5% at 40 x 30, 64 spp, the same on both devices; either mean's
// noise is below 0.3%).
TEST(RenderCli, SingleScatteringIsRecordedAndDarkensTheRoughLobes) {
    const test::TempDir dir;
    const std::string scene = test::sourcePath("assets/material_spheres.gltf").string();
    for (const std::string device : {"gpu", "cpu"}) {
        SCOPED_TRACE(device);
        const auto mean = [&](const std::string& flag, const std::string& recorded) {
            const std::string exr = (dir / (device + flag + ".exr")).string();
            const auto r = test::runVkpath("render " + scene + " -d 32x24 -s 32 -m 4 --device " +
                                           device + " " + flag + " -o " + exr);
            EXPECT_EQ(r.exitCode, 0) << r.err;
            EXPECT_EQ(vkpathMetadata(exr)["vkpath:microfacet"], recorded);
            const image::Image image = image::readImage(exr);
            double sum = 0;
            for (const glm::vec3& p : image.pixels) sum += p.x + p.y + p.z;
            return sum / (3.0 * image.pixels.size());
        };
        const double compensated = mean("", "compensated");
        const double single = mean("--single-scattering", "single-scattering");
        std::printf("  %s: image mean %.4f compensated, %.4f single scattering (ratio %.4f)\n",
                    device.c_str(), compensated, single, compensated / single);
        EXPECT_GT(compensated, 1.02 * single);
    }
}

// --variant renders a glTF material variant (KHR_materials_variants) and
// records it; a name the file does not declare is one line, exit 2, nothing
// written. The file: a red triangle whose variant "green" is green, under a
// white sky, filling the middle of the film.
TEST(RenderCli, VariantChoosesTheMaterialsAndAnUnknownOneIsOneLine) {
    const test::TempDir dir;
    test::GltfBuilder b;
    b.material(
        {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 0}}}});
    b.material(
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 1, 0, 1}}, {"metallicFactor", 0}}}});
    b.node({{"mesh", b.triangle(0)}});
    b.doc["cameras"].push_back(
        {{"type", "perspective"}, {"perspective", {{"yfov", 0.2}, {"znear", 0.01}}}});
    b.node({{"camera", 0}, {"translation", {0.3, 0.3, 5}}});
    b.doc["extensions"]["KHR_materials_variants"]["variants"] = {{{"name", "green"}}};
    b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"] = {
        {{"material", 1}, {"variants", {0}}}};
    const std::string scene = b.writeGltf(dir / "variants.gltf").string();
    const auto colour = [&](const std::string& flags) {
        const std::string exr = (dir / "v.exr").string();
        const auto r = test::runVkpath("render " + scene + " -d 8x8 -s 4 --env-color 1,1,1 " +
                                       flags + " -o " + exr);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        const image::Image image = image::readImage(exr);
        const glm::vec3 centre = image.pixels[4 * 8 + 4];
        return std::pair{centre, vkpathMetadata(exr)["vkpath:variant"]};
    };
    const auto [own, ownRecorded] = colour("");
    EXPECT_GT(own.x, 10 * own.y) << "red";
    EXPECT_EQ(ownRecorded, "");
    const auto [green, recorded] = colour("--variant green");
    EXPECT_GT(green.y, 10 * green.x) << "green";
    EXPECT_EQ(recorded, "green");

    const std::string exr = (dir / "x.exr").string();
    const auto r = test::runVkpath("render " + scene + " -d 8x8 --variant blue -o " + exr);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("no material variant named 'blue' (the file's: 'green')"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(exr));
}

// The preview is the EXR, scaled by 2^exposure and sRGB-encoded to 8 bits.
TEST(RenderCli, PngPreviewIsTheExrInSrgbWithExposure) {
    const test::TempDir dir;
    const std::string exr = (dir / "box.exr").string(), png = (dir / "box.png").string();
    const auto r = test::runVkpath("render " + cornellBox() + " -d 20x16 -s 2 -o " + exr +
                                   " --png " + png + " --exposure 1.5");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const image::Image linear = image::readImage(exr);
    const auto bytes = storedPixels(png, OIIO::TypeDesc::UINT8);
    ASSERT_EQ(bytes.size(), linear.pixels.size() * 3);
    int mismatches = 0, clipped = 0, lit = 0;
    for (size_t i = 0; i < linear.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = linear.pixels[i][c] * std::exp2(1.5f);
            const long expected = std::lround(image::linearToSrgb(v) * 255.0f);
            if (std::abs(long(bytes[3 * i + c]) - expected) > 0) ++mismatches;
            clipped += v >= 1.0f;
            lit += v > 0.0f;
        }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(lit, 0);
    EXPECT_GT(clipped, 0) << "the lamp, 17 W/(m^2 sr), clips";
}

// The same scene, flags and seed: the same pixels, bit for bit, and the same
// header but for the render time. A different seed gives other pixels.
TEST(RenderCli, SameSeedSamePixelBytes) {
    const test::TempDir dir;
    auto render = [&](const std::string& name, const std::string& flags) {
        const std::string path = (dir / name).string();
        const auto r =
            test::runVkpath("render " + cornellBox() + " -d 24x18 -s 4 -o " + path + " " + flags);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return path;
    };
    const std::string a = render("a.exr", "--seed 5"), b = render("b.exr", "--seed 5"),
                      c = render("c.exr", "--seed 6");
    const auto pa = storedPixels(a, OIIO::TypeDesc::FLOAT),
               pb = storedPixels(b, OIIO::TypeDesc::FLOAT);
    ASSERT_FALSE(pa.empty());
    EXPECT_EQ(pa, pb);
    EXPECT_NE(pa, storedPixels(c, OIIO::TypeDesc::FLOAT));
    auto ma = vkpathMetadata(a), mb = vkpathMetadata(b);
    ma.erase("vkpath:renderSeconds");
    mb.erase("vkpath:renderSeconds");
    EXPECT_EQ(ma, mb);
}

// --device cpu says which build of the integrator it runs; --no-specialize
// takes the general one, with the same pixels. --kernel is the GPU's alone.
TEST(RenderCli, CpuReferenceNamesItsBuildAndNoSpecializeKeepsThePixels) {
    const test::TempDir dir;
    auto render = [&](const std::string& name, const std::string& flags) {
        const std::string path = (dir / name).string();
        const auto r = test::runVkpath(
            "render " + test::sourcePath("assets/cornell_box_diffuse.gltf").string() +
            " -d 24x18 -s 2 --device cpu -o " + path + " " + flags);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return std::pair{path, r.err};
    };
    const auto [profile, profileLog] = render("profile.exr", "");
    EXPECT_NE(profileLog.find("the integrator built for the 'smooth' profile"), std::string::npos)
        << profileLog;
    const auto [general, generalLog] = render("general.exr", "--no-specialize");
    EXPECT_NE(generalLog.find("the integrator's general build (--no-specialize)"),
              std::string::npos)
        << generalLog;
    const auto pixels = storedPixels(profile, OIIO::TypeDesc::FLOAT);
    ASSERT_FALSE(pixels.empty());
    EXPECT_EQ(pixels, storedPixels(general, OIIO::TypeDesc::FLOAT));

    const std::string exr = (dir / "x.exr").string();
    const auto r = test::runVkpath("render " + cornellBox() +
                                   " -d 8x8 --device cpu --kernel megakernel -o " + exr);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(exr));
}

// --time-budget without -s renders past the default 16 spp until the budget
// is spent, and records the spp it reached.
TEST(RenderCli, TimeBudgetRendersUntilSpentAndRecordsTheSppReached) {
    const test::TempDir dir;
    const std::string exr = (dir / "budget.exr").string();
    // 32 x 32 pixels and 2^10 paths per wave: one sample per wave.
    const auto r =
        test::runVkpath("render " + cornellBox() +
                        " -d 32x32 -m 2 --paths-in-flight 1024 --time-budget 1 -o " + exr);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Summary s = parseSummary(r.err);
    ASSERT_TRUE(s.found) << r.err;
    EXPECT_GT(s.spp, 16u) << "the budget, not the default sample count, ends the render";
    const auto m = vkpathMetadata(exr);
    EXPECT_EQ(m.at("vkpath:spp"), std::to_string(s.spp));
    // Stopping within one wave is TimeBudget.StopsWithinOneWave's (in process,
    // timed per wave); here the bound only says the budget ended the render,
    // with room for a busy machine's scheduling (one wave is a few ms).
    const double seconds = std::stod(m.at("vkpath:renderSeconds"));
    EXPECT_GE(seconds, 1.0);
    EXPECT_LE(seconds, 1.5);
}

TEST(RenderCli, TimeBudgetWithSppStopsAtTheSpp) {
    const test::TempDir dir;
    const std::string exr = (dir / "capped.exr").string();
    const auto r =
        test::runVkpath("render " + cornellBox() + " -d 8x8 -s 3 --time-budget 100 -o " + exr);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(vkpathMetadata(exr).at("vkpath:spp"), "3");
}

// On a terminal a progress bar runs on stderr (samples done, Mpaths/s, ETA),
// redrawn in place; piped, stderr carries only the summary. The terminal is a
// pseudo-terminal from util-linux's `script`.
TEST(RenderCli, ProgressBarOnATerminalOnly) {
    const test::TempDir dir;
    const std::string exr = (dir / "p.exr").string(), log = (dir / "tty.txt").string();
    const std::string render = std::string("'") + VKPATH_BINARY + "' render " + cornellBox() +
                               " -d 16x16 -s 8 --paths-in-flight 256 -o " + exr;
    const std::string command =
        "script -qec \"" + render + "\" /dev/null > '" + log + "' 2>&1 </dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(log);
    const std::string tty((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(tty.find("8/8 spp"), std::string::npos) << tty;
    EXPECT_NE(tty.find("Mpaths/s  ETA"), std::string::npos) << tty;
    EXPECT_NE(tty.find('\r'), std::string::npos) << "the bar is redrawn in place";
    const auto piped = test::runVkpath(render.substr(render.find("' ") + 2));
    ASSERT_EQ(piped.exitCode, 0) << piped.err;
    EXPECT_EQ(piped.err.find("ETA"), std::string::npos) << piped.err;
    EXPECT_EQ(piped.err.find('\r'), std::string::npos);
}

TEST(RenderCli, BadTimeBudgetIsOneLineAndNothingWritten) {
    const test::TempDir dir;
    for (const char* budget : {"0", "-1", "nan"})
        expectRefusedInOneLine(dir, "--time-budget " + std::string(budget));
}

// --fog-density fills the scene with fog: recorded in the EXR (and in the
// identity, so a checkpoint without fog is not resumed with it), and the box
// seen through 1/m of it is darker. A density of two numbers, a negative one,
// an albedo above 1 or an anisotropy of 1 is one line, exit 2, nothing written.
TEST(RenderCli, FogIsRecordedDarkensTheBoxAndBadFogIsOneLine) {
    const test::TempDir dir;
    const auto mean = [&](const std::string& flags, const char* name) {
        const std::string exr = (dir / name).string();
        const auto r = test::runVkpath("render " + cornellBox() + " -d 16x16 -s 16 -m 3 " + flags +
                                       " -o " + exr);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        const image::Image image = image::readImage(exr);
        double sum = 0;
        for (const glm::vec3& p : image.pixels) sum += p.x + p.y + p.z;
        return std::pair(sum / (3.0 * image.pixels.size()), vkpathMetadata(exr));
    };
    const auto [clear, clearMetadata] = mean("", "clear.exr");
    const auto [foggy, foggyMetadata] =
        mean("--fog-density 1 --fog-albedo 0.5,0.6,0.7 --fog-anisotropy 0.2", "foggy.exr");
    EXPECT_EQ(clearMetadata.count("vkpath:fog"), 0u);
    EXPECT_EQ(foggyMetadata.at("vkpath:fog"),
              "scattering 0.5 0.6 0.7, absorption 0.5 0.4 0.3, anisotropy 0.2 (per metre)");
    EXPECT_NE(foggyMetadata.at("vkpath:settings").find("\"fog\""), std::string::npos);
    EXPECT_LT(foggy, 0.9 * clear);
    for (const char* flags :
         {"--fog-density 1,2", "--fog-density -1", "--fog-density 1 --fog-albedo 1.5",
          "--fog-density 1 --fog-anisotropy 1", "--fog-density nan"})
        expectRefusedInOneLine(dir, flags);
}

// --volume FILE.vdb adds a grid medium: recorded in the EXR (vkpath:volume)
// and in the identity, darker than without. A file that is not a grid
// file, a grid name the file lacks (the message lists its grids) and an
// albedo of two numbers are one line, exit 2, nothing written.
TEST(RenderCli, VolumeIsRecordedAndBadVolumesAreOneLine) {
    const test::TempDir dir;
    const auto grid = test::writeGrid(dir / "smoke.vdb", 12, 0.03, {-0.15, 0.1, -0.4},
                                      [](int, int, int) { return 1.0f; });
    const std::string exr = (dir / "smoky.exr").string();
    const auto r = test::runVkpath("render " + cornellBox() + " -d 16x16 -s 8 -m 3 --volume " +
                                   grid.string() + " --volume-density 20 -o " + exr);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto metadata = vkpathMetadata(exr);
    EXPECT_NE(metadata.at("vkpath:volume").find("grid 'density', density 20"), std::string::npos)
        << metadata.at("vkpath:volume");
    EXPECT_NE(metadata.at("vkpath:settings").find("\"volume\""), std::string::npos);
    std::ofstream(dir / "not.vdb") << "no grid here";
    const std::vector<std::string> badFlags = {
        "--volume " + (dir / "not.vdb").string(),
        "--volume " + grid.string() + " --volume-grid smoke",
        "--volume " + grid.string() + " --volume-albedo 0.5,0.5"};
    for (const std::string& flags : badFlags) expectRefusedInOneLine(dir, flags);
}

// Flags that would write nonsense or run for hours before a sample.
TEST(RenderCli, RunawayOrNonsenseFlagsAreOneLineAndNothingWritten) {
    const test::TempDir dir;
    for (const char* flags : {"--exposure nan", "--exposure inf", "-l 100000", "-m 100000",
                              "--guide-spheres 1", "--guide-spheres -0.1", "--guide-spheres nan"})
        expectRefusedInOneLine(dir, flags);
}

// --max-wave-ms: waves sized to the cap (the first is one workgroup's worth,
// and a 24576-path wave takes ~70 ms here, far over 1 ms) give the same
// pixels bit for bit as one wave of every path, in either kernel form.
TEST(RenderCli, MaxWaveMsKeepsThePixelsBitForBitInMoreWaves) {
    const test::TempDir dir;
    static const std::regex wavesOf(R"((\d+) waves of \d+ paths)");
    for (const char* kernel : {"wavefront", "megakernel"}) {
        SCOPED_TRACE(kernel);
        auto render = [&](const std::string& name, const std::string& flags, uint32_t& waves) {
            const std::string path = (dir / name).string();
            const auto r = test::runVkpath("render " + cornellBox() + " -d 64x48 -s 8 --kernel " +
                                           kernel + " -o " + path + " " + flags);
            EXPECT_EQ(r.exitCode, 0) << r.err;
            std::smatch m;
            EXPECT_TRUE(std::regex_search(r.err, m, wavesOf)) << r.err;
            waves = m.empty() ? 0 : uint32_t(std::stoul(m[1]));
            return std::make_pair(path, r.err);
        };
        uint32_t whole = 0, capped = 0;
        const auto [a, aErr] = render(std::string(kernel) + ".exr", "", whole);
        const auto [b, bErr] =
            render(std::string(kernel) + "-capped.exr", "--max-wave-ms 1", capped);
        EXPECT_EQ(whole, 1u);
        EXPECT_GT(capped, whole);
        EXPECT_NE(bErr.find("waves capped at 1 ms: "), std::string::npos) << bErr;
        EXPECT_EQ(aErr.find("waves capped"), std::string::npos) << aErr;
        const auto pa = storedPixels(a, OIIO::TypeDesc::FLOAT);
        ASSERT_FALSE(pa.empty());
        EXPECT_EQ(pa, storedPixels(b, OIIO::TypeDesc::FLOAT));
    }
}

// A bound on device memory makes the waves smaller, not the image different;
// one that leaves no room for paths is refused before rendering.
TEST(RenderCli, MaxDeviceMemoryMakesWavesSmallerNotTheImage) {
    const test::TempDir dir;
    const std::string a = (dir / "a.exr").string(), b = (dir / "b.exr").string();
    const std::string common = "render " + cornellBox() + " -d 64x48 -s 8 --kernel wavefront ";
    const auto whole = test::runVkpath(common + "-o " + a);
    ASSERT_EQ(whole.exitCode, 0) << whole.err;
    EXPECT_NE(whole.err.find("1 waves of 24576 paths"), std::string::npos) << whole.err;
    // The path state of 24576 paths is 3.5 MiB; 1 MiB holds one sample's 3072.
    const auto bounded = test::runVkpath(common + "--max-device-memory 1 -o " + b);
    ASSERT_EQ(bounded.exitCode, 0) << bounded.err;
    EXPECT_NE(bounded.err.find("8 waves of 3072 paths"), std::string::npos) << bounded.err;
    static const std::regex memory(R"(device memory ([0-9.]+) MiB)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(bounded.err, m, memory)) << bounded.err;
    EXPECT_LE(std::stod(m[1]), 1.0);
    const auto pa = storedPixels(a, OIIO::TypeDesc::FLOAT);
    ASSERT_FALSE(pa.empty());
    EXPECT_EQ(pa, storedPixels(b, OIIO::TypeDesc::FLOAT));

    const std::string c = (dir / "c.exr").string();
    const auto tiny = test::runVkpath(common + "--max-device-memory 0.1 -o " + c);
    EXPECT_EQ(tiny.exitCode, 2) << tiny.err;
    EXPECT_EQ(test::lineCount(tiny.err), 1) << tiny.err;
    EXPECT_NE(tiny.err.find("the scene and the film take"), std::string::npos) << tiny.err;
    EXPECT_FALSE(std::filesystem::exists(c));
}

TEST(RenderCli, BadMaxWaveMsOrMaxDeviceMemoryIsOneLineAndNothingWritten) {
    const test::TempDir dir;
    for (const char* flag : {"--max-wave-ms", "--max-device-memory"}) {
        for (const char* value : {"0", "-1", "nan", "inf"}) {
            SCOPED_TRACE(std::string(flag) + " " + value);
            const std::string exr = (dir / "x.exr").string();
            const auto r = test::runVkpath("render " + cornellBox() + " -d 8x8 " + flag + " " +
                                           value + " -o " + exr);
            EXPECT_EQ(r.exitCode, 2);
            EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
            EXPECT_NE(r.err.find(flag), std::string::npos) << r.err;
            EXPECT_FALSE(std::filesystem::exists(exr));
        }
    }
}

}  // namespace
