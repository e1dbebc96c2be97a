// render --denoise and vkpath denoise: Intel Open Image Denoise 2 from PyPI's
// pyoidn wheel (tools/oidn-venv, which `make test` runs), loaded at run time
// (image/denoiser.h). Skipped, saying why, where the library is not there.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "image/image.h"
#include "image/metrics.h"
#include "image/statistics.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;

// The library tools/oidn-venv installs beside the vkpath under test, or
// VKPATH_OIDN_LIBRARY's; empty when neither is there.
std::string oidnLibrary() {
    if (const char* set = std::getenv("VKPATH_OIDN_LIBRARY"); set && *set) return set;
    const fs::path lib = fs::path(VKPATH_BINARY).parent_path() / "oidn-venv" / "lib";
    std::error_code ec;
    for (const auto& python : fs::directory_iterator(lib, ec)) {
        const fs::path candidate = python.path() / "site-packages" / "pyoidn" / "oidn" / "lib" /
                                   "libOpenImageDenoise.so.2";
        if (fs::exists(candidate)) return candidate.string();
    }
    return {};
}

// VKPATH_OIDN_LIBRARY for the command lines a test runs.
class OidnLibrary {
  public:
    explicit OidnLibrary(const std::string& path) {
        setenv("VKPATH_OIDN_LIBRARY", path.c_str(), 1);
    }
    ~OidnLibrary() { unsetenv("VKPATH_OIDN_LIBRARY"); }
    OidnLibrary(const OidnLibrary&) = delete;
    OidnLibrary& operator=(const OidnLibrary&) = delete;
};

#define VKPATH_SKIP_WITHOUT_OIDN(path)                                                       \
    const std::string path = oidnLibrary();                                                  \
    if (path.empty())                                                                        \
        GTEST_SKIP() << "no Open Image Denoise: run tools/oidn-venv (PyPI's pyoidn) or set " \
                        "VKPATH_OIDN_LIBRARY";

std::string diffuseBox() {
    return test::sourcePath("assets/cornell_box_diffuse.gltf").string();
}

double relMse(const fs::path& a, const fs::path& b) {
    return image::compareImages(image::readImage(a), image::readImage(b)).overall.relMse;
}

// render --denoise keeps the raw render in -o and writes the denoised one
// beside it, marked as such, guided by the albedo and normal AOVs
// (prefiltered); `vkpath denoise --prefilter` of the raw EXR with those AOVs
// gives the same pixels. At 16 spp, 160 x 120, the denoised diffuse box is
// closer to a 512-spp render of another seed than the raw one: relMSE
// measured 5.3 and 5.4 times lower (seeds 1 and 2; 4.6 and 4.6 with the
// guides not prefiltered, 5.0 and 4.6 without guides); the bound is 3 (a
// denoiser that does nothing, or blurs the walls into each other, fails it).
TEST(Denoise, RenderKeepsTheRawImageAndWritesADenoisedOneCloserToTheTruth) {
    VKPATH_SKIP_WITHOUT_OIDN(library);
    const OidnLibrary use(library);
    const test::TempDir dir;
    const fs::path reference = dir / "reference.exr", raw = dir / "raw.exr";
    ASSERT_EQ(test::runVkpath("render " + diffuseBox() + " -d 160x120 -s 512 --seed 99 -o " +
                              reference.string())
                  .exitCode,
              0);
    const auto r = test::runVkpath("render " + diffuseBox() +
                                   " -d 160x120 -s 16 --seed 1 --denoise --aov albedo,normal -o " +
                                   raw.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const fs::path denoised = image::aovPath(raw, "denoised");
    ASSERT_TRUE(fs::exists(denoised)) << r.err;
    EXPECT_EQ(image::readVkpathMetadata(raw).count("vkpath:denoised"), 0u);
    EXPECT_EQ(image::readVkpathMetadata(denoised).at("vkpath:denoised"),
              "Intel Open Image Denoise 2, RT filter, hdr, guides: albedo, normal (prefiltered, "
              "cleanAux)");
    EXPECT_EQ(image::readVkpathMetadata(denoised).at("vkpath:spp"), "16");
    const double rawError = relMse(raw, reference), denoisedError = relMse(denoised, reference);
    RecordProperty("raw_over_denoised_relmse", std::to_string(rawError / denoisedError));
    EXPECT_LT(denoisedError * 3, rawError) << rawError << " raw, " << denoisedError << " denoised";

    const fs::path again = dir / "again.exr";
    const auto d = test::runVkpath("denoise " + raw.string() + " --albedo " +
                                   image::aovPath(raw, "albedo").string() + " --normal " +
                                   image::aovPath(raw, "normal").string() + " --prefilter -o " +
                                   again.string() + " --png " + (dir / "again.png").string());
    ASSERT_EQ(d.exitCode, 0) << d.err;
    EXPECT_TRUE(fs::exists(dir / "again.png"));
    EXPECT_EQ(image::readImage(again).pixels, image::readImage(denoised).pixels);
}

// converge --denoise: the same checkpoints, each denoised before it is
// measured against the reference (the CSV's relMSE is the denoised image's),
// the denoiser's time in its wall time; without a reference one line, since
// the two-seed estimate cannot see what a denoiser does to the image.
TEST(Denoise, ConvergeMeasuresTheDenoisedImage) {
    VKPATH_SKIP_WITHOUT_OIDN(library);
    const OidnLibrary use(library);
    const test::TempDir dir;
    const fs::path reference = dir / "reference.exr";
    ASSERT_EQ(test::runVkpath("render " + diffuseBox() + " -d 160x120 -s 256 --seed 99 -o " +
                              reference.string())
                  .exitCode,
              0);
    auto relMseAt16 = [&](const std::string& flags) {
        const fs::path csv = dir / "c.csv";
        const auto r =
            test::runVkpath("converge " + diffuseBox() + " -d 160x120 --spp 4,16 --reference " +
                            reference.string() + " --csv " + csv.string() + " --plot " +
                            (dir / "c.png").string() + flags);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        std::ifstream in(csv);
        std::string line, last;
        while (std::getline(in, line)) last = line;
        // knob,value,spp,wall_seconds,device_seconds,relmse,...
        std::vector<std::string> fields;
        std::stringstream row(last);
        for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
        EXPECT_EQ(fields.at(2), "16");
        return std::stod(fields.at(5));
    };
    const double raw = relMseAt16(""), denoised = relMseAt16(" --denoise");
    EXPECT_LT(denoised * 3, raw) << raw << " raw, " << denoised << " denoised";
    const auto alone =
        test::runVkpath("converge " + diffuseBox() + " -d 16x12 --spp 1,2 --denoise --csv " +
                        (dir / "x.csv").string());
    EXPECT_EQ(alone.exitCode, 2) << alone.err;
    EXPECT_EQ(test::lineCount(alone.err), 1) << alone.err;
}

// Without the library: one line saying how to install it, exit code 2,
// before any rendering and with nothing written. Guides of another size, or
// a normal guide without an albedo one, are one line too.
TEST(Denoise, NoLibraryOrMismatchedGuidesAreOneLine) {
    const test::TempDir dir;
    const fs::path exr = dir / "box.exr";
    {
        const OidnLibrary missing((dir / "libOpenImageDenoise.so.2").string());
        const auto r = test::runVkpath("render " + diffuseBox() + " -d 16x12 -s 2 --denoise -o " +
                                       exr.string());
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
        EXPECT_NE(r.err.find("pip install pyoidn"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(exr));
    }
    ASSERT_EQ(
        test::runVkpath("render " + diffuseBox() + " -d 16x12 -s 2 -o " + exr.string()).exitCode,
        0);
    const fs::path small = dir / "small.exr";
    ASSERT_EQ(
        test::runVkpath("render " + diffuseBox() + " -d 8x6 -s 2 -o " + small.string()).exitCode,
        0);
    const auto normalAlone = test::runVkpath("denoise " + exr.string() + " --normal " +
                                             exr.string() + " -o " + (dir / "x.exr").string());
    EXPECT_EQ(normalAlone.exitCode, 2) << normalAlone.err;
    VKPATH_SKIP_WITHOUT_OIDN(library);
    const OidnLibrary use(library);
    const auto mismatch = test::runVkpath("denoise " + exr.string() + " --albedo " +
                                          small.string() + " -o " + (dir / "x.exr").string());
    EXPECT_EQ(mismatch.exitCode, 2) << mismatch.err;
    EXPECT_EQ(test::lineCount(mismatch.err), 1) << mismatch.err;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

}  // namespace
