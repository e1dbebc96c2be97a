// Textured models of Debian's assimp-testmodels (made by others; read where
// the package puts them), rendered by `vkpath render` as a user would, and
// judged against what their texture files say, decoded here with OpenImageIO
// and the sRGB rule written out (not the renderer's decoder).
//
// BoxTextured: a diffuse box under a constant white sky. The box is convex,
// so every direction above a face sees the sky: a face of albedo a (the
// texture, times a base colour factor of 1) reflects a x (1 / pi) x pi x 1 = a
// exactly in expectation, and the light bounces no further. Each face's
// texture coordinates cover the whole image once (u over [k, k + 1], mirrored
// on alternate faces, v over [0, 1] clamped), and the bilinear reconstruction
// between texel centres integrates to the texels' mean over a whole period
// (each texel weighs 1 / N per axis, the half texels at the edges held
// constant), so the face's mean radiance is the texels' mean, in linear RGB.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "image/image.h"
#include "image/statistics.h"
#include "scene/camera.h"
#include "scene/load.h"
#include "shared/camera.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;

const fs::path MODELS = "/usr/share/assimp/models";
constexpr int TIMEOUT_SECONDS = 120;

#define SKIP_WITHOUT_PACKAGE()                                                                             \
    if (!fs::is_directory(MODELS))                                                                        \
    GTEST_SKIP() << MODELS << " is missing: Debian's assimp-testmodels is not installed (tools/install-deps)"

// IEC 61966-2-1, in double: the rule glTF 2.0 gives for base colour textures.
double srgbToLinear(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// An image file's texels as 8-bit RGB, rows from the top.
struct Texels {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

Texels readTexels(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw std::runtime_error(path.string() + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    Texels t;
    t.width = spec.width;
    t.height = spec.height;
    std::vector<uint8_t> all(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, all.data()))
        throw std::runtime_error(path.string() + ": " + in->geterror());
    for (size_t i = 0; i < size_t(spec.width) * spec.height; ++i)
        for (int c = 0; c < 3; ++c) t.rgb.push_back(all[i * spec.nchannels + std::min(c, spec.nchannels - 1)]);
    return t;
}

// The mean texel over [x0, x1) x [y0, y1), per channel, each texel decoded
// by `decode` (sRGB to linear, or not, for the power checks).
glm::dvec3 meanTexel(const Texels& t, int x0, int y0, int x1, int y1, double (*decode)(double)) {
    glm::dvec3 sum(0.0);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c) sum[c] += decode(t.rgb[(size_t(y) * t.width + x) * 3 + c] / 255.0);
    return sum / double(size_t(x1 - x0) * size_t(y1 - y0));
}

double identity(double v) { return v; }

scene::Scene loadQuiet(const fs::path& path) {
    testing::internal::CaptureStderr();
    try {
        scene::Scene s = scene::loadScene(path);
        testing::internal::GetCapturedStderr();
        return s;
    } catch (...) {
        testing::internal::GetCapturedStderr();
        throw;
    }
}

// Where a world point lands on the film, in pixels from the top-left corner
// (shared/camera.h's generateCameraRay inverted).
glm::dvec2 project(const shared::Camera& c, glm::dvec3 p) {
    const glm::dvec3 d = p - glm::dvec3(c.origin);
    const glm::dvec3 forward(c.forward), right(c.right), up(c.up);
    const double t = glm::dot(d, forward);
    const double ndcX = glm::dot(d, right) / (t * glm::dot(right, right));
    const double ndcY = glm::dot(d, up) / (t * glm::dot(up, up));
    return {(ndcX + 1.0) * 0.5 * c.width, (1.0 - ndcY) * 0.5 * c.height};
}

struct Render {
    image::Image image, variance;  // variance of each pixel's mean
};

// `vkpath render` with a white sky and the variance AOV; fails the test on
// anything but exit 0.
Render render(const fs::path& scene, uint32_t width, uint32_t height, int spp, const std::string& extra = {}) {
    const test::TempDir dir;
    const fs::path exr = dir / "out.exr";
    const test::CommandResult r = test::runVkpath(
        "--validation render '" + scene.string() + "' -d " + std::to_string(width) + "x" + std::to_string(height) +
            " -s " + std::to_string(spp) + " --env-color 1,1,1 --aov variance -o '" + exr.string() + "' " + extra,
        TIMEOUT_SECONDS);
    Render out;
    EXPECT_EQ(r.exitCode, 0) << scene << ":\n" << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    if (r.exitCode != 0) return out;
    out.image = image::readImage(exr);
    out.variance = image::readImage(image::aovPath(exr, "variance"));
    return out;
}

// ---------------------------------------------------------------------------
// BoxTextured: the face the default camera sees shows the texture's mean
// ---------------------------------------------------------------------------

// The three containers of the same model: the PNG as a file, as a data: URI
// and in the GLB's binary chunk (the same 2433 bytes in each).
class BoxTextured : public testing::TestWithParam<const char*> {};

TEST_P(BoxTextured, FaceShowsTheTexturesMeanColour) {
    SKIP_WITHOUT_PACKAGE();
    const fs::path folder = MODELS / "glTF2";
    const fs::path file = folder / GetParam();
    constexpr uint32_t W = 64, H = 48;
    constexpr int SPP = 64;

    // The geometry the argument above rests on: the unit cube about the
    // origin, framed by vkpath's default camera (no camera in the file) from
    // +z on the z axis, so that the face z = 0.5 faces it and hides the
    // other five (their outlines project inside its own).
    const scene::Scene s = loadQuiet(file);
    const scene::Bounds b = s.geometryBounds();
    ASSERT_EQ(b.lo, glm::vec3(-0.5f));
    ASSERT_EQ(b.hi, glm::vec3(0.5f));
    const shared::Camera camera = scene::makeGpuCamera(s.camera, W, H);
    ASSERT_NEAR(camera.origin.x, 0.0f, 1e-6f);
    ASSERT_NEAR(camera.origin.y, 0.0f, 1e-6f);
    ASSERT_GT(camera.origin.z, 0.5f);
    ASSERT_NEAR(camera.forward.z, -1.0f, 1e-6f);

    // The face's rectangle on the film: a plane parallel to the film maps to
    // it by a similarity, so its area in pixels is exact.
    const glm::dvec2 lo = project(camera, {-0.5, 0.5, 0.5}), hi = project(camera, {0.5, -0.5, 0.5});
    const double faceArea = (hi.x - lo.x) * (hi.y - lo.y);
    // Every pixel the face touches plus a margin of sky (radiance exactly 1,
    // seen directly), well inside the film.
    const int x0 = int(std::floor(lo.x)) - 2, x1 = int(std::ceil(hi.x)) + 2;
    const int y0 = int(std::floor(lo.y)) - 2, y1 = int(std::ceil(hi.y)) + 2;
    ASSERT_GE(x0, 0);
    ASSERT_GE(y0, 0);
    ASSERT_LE(x1, int(W));
    ASSERT_LE(y1, int(H));
    ASSERT_GT(faceArea, 500.0) << "the face covers " << faceArea << " pixels";

    const Render r = render(file, W, H, SPP);
    ASSERT_EQ(r.image.width, W);
    ASSERT_EQ(r.variance.width, W);

    // Sum over the region = faceArea x (face mean) + (the rest) x 1.
    glm::dvec3 sum(0.0), variance(0.0);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            sum += glm::dvec3(r.image.at(uint32_t(x), uint32_t(y)));
            variance += glm::dvec3(r.variance.at(uint32_t(x), uint32_t(y)));
        }
    const double regionArea = double(x1 - x0) * double(y1 - y0);
    const glm::dvec3 faceMean = (sum - (regionArea - faceArea)) / faceArea;
    const glm::dvec3 standardError = glm::sqrt(variance) / faceArea;

    const Texels texture = readTexels(folder / "BoxTextured-glTF" / "CesiumLogoFlat.png");
    const glm::dvec3 expected = meanTexel(texture, 0, 0, texture.width, texture.height, srgbToLinear);
    const glm::dvec3 undecoded = meanTexel(texture, 0, 0, texture.width, texture.height, identity);
    for (int c = 0; c < 3; ++c) {
        // 5 standard errors (false alarm 6e-7 per channel), plus the texel
        // store's rounding to half floats (at most 2^-11 of each texel, so
        // of their mean).
        const double bound = 5.0 * standardError[c] + std::ldexp(expected[c], -11);
        EXPECT_NEAR(faceMean[c], expected[c], bound)
            << "channel " << c << ": " << faceArea << " pixels of face, standard error " << standardError[c];
        // Power: the texels' mean without sRGB decoding is far outside it.
        EXPECT_GT(std::abs(faceMean[c] - undecoded[c]), 4.0 * bound) << "channel " << c;
    }
}

INSTANTIATE_TEST_SUITE_P(AssimpTestModels, BoxTextured,
                         testing::Values("BoxTextured-glTF/BoxTextured.gltf",
                                         "BoxTextured-glTF-Embedded/BoxTextured.gltf",
                                         "BoxTextured-glTF-Binary/BoxTextured.glb"),
                         [](const testing::TestParamInfo<const char*>& param) {
                             return std::string(param.index == 0   ? "File"
                                                : param.index == 1 ? "DataUri"
                                                                   : "GlbChunk");
                         });

}  // namespace
