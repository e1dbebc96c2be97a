// Textured glTF models of Debian's assimp-testmodels (made by others; read
// where the package puts them), rendered as a user would (TextureTransformTest
// by `vkpath render`; BoxTextured through the library, its material's
// specular layer taken off), and judged against what their texture files say,
// decoded in the test (tests/support/textured_render.h), not by the renderer's
// decoder.
//
// BoxTextured: its Lambertian base under a constant white sky. The box is convex,
// so every direction above a face sees the sky: a face of albedo a (the
// texture, times a base colour factor of 1) reflects a x (1 / pi) x pi x 1 = a
// exactly in expectation, and the light bounces no further. Each face's
// texture coordinates cover the whole image once (u over [k, k + 1], mirrored
// on alternate faces, v over [0, 1] clamped), and the bilinear reconstruction
// between texel centres integrates to the texels' mean over a whole period
// (each texel weighs 1 / N per axis, the half texels at the edges held
// constant), so the face's mean radiance is the texels' mean, in linear RGB.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "image/image.h"
#include "scene/camera.h"
#include "scene/load.h"
#include "shared/camera.h"
#include "support/temp_dir.h"
#include "support/test_context.h"
#include "support/textured_render.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;

const fs::path MODELS = "/usr/share/assimp/models";

#define SKIP_WITHOUT_PACKAGE()     \
    if (!fs::is_directory(MODELS)) \
    GTEST_SKIP()                   \
        << MODELS                  \
        << " is missing: Debian's assimp-testmodels is not installed (tools/install-deps)"

double identity(double v) {
    return v;
}

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
    // glTF's non-metal (base colour factor 1, metallic 0, roughness 1): a
    // dielectric layer over a Lambertian base of the texture's colour. What
    // this test checks is the texture's way from the file to the film, so it
    // renders the base alone: the same material without its specular layer
    // (KHR_materials_specular's specularFactor 0, which is exactly
    // Lambertian; the layer is tests/kernels/material_bsdf_test.cpp's).
    ASSERT_EQ(s.meshes.size(), 1u);
    scene::Scene lambertian = s;
    scene::Material& m = lambertian.materials.at(s.meshes[0].material);
    ASSERT_EQ(m.kind, scene::MaterialKind::MetallicRoughness);
    ASSERT_EQ(m.metallic, 0.0f);
    ASSERT_EQ(m.reflectance, glm::vec3(1.0f));
    ASSERT_TRUE(m.baseColorTexture.present());
    ASSERT_FALSE(m.emissive());
    m.kind = scene::MaterialKind::Diffuse;
    m.specular = 0.0f;
    scene::Environment sky;
    sky.color = glm::vec3(1.0f);
    lambertian.environment = sky;

    // The face's rectangle on the film: a plane parallel to the film maps to
    // it by a similarity, so its area in pixels is exact.
    const glm::dvec2 lo = test::project(camera, {-0.5, 0.5, 0.5}),
                     hi = test::project(camera, {0.5, -0.5, 0.5});

    wavefront::RenderSettings settings;
    settings.width = W;
    settings.height = H;
    settings.samplesPerPixel = SPP;
    wavefront::GpuRenderer renderer(test::context(), lambertian, settings);
    const wavefront::RenderResult result = renderer.render();
    const test::Render r{result.image, result.varianceOfMean};
    ASSERT_EQ(r.image.width, W);
    const test::FaceMean face = test::faceMeanOnWhiteSky(r, lo, hi);
    ASSERT_TRUE(face.inside) << "the face and its margin lie on the film";
    ASSERT_GT(face.area, 500.0);

    const test::Texels texture =
        test::readTexels(folder / "BoxTextured-glTF" / "CesiumLogoFlat.png");
    const glm::dvec3 expected = test::meanTexel(texture, test::srgbToLinear);
    const glm::dvec3 undecoded = test::meanTexel(texture, identity);
    for (int c = 0; c < 3; ++c) {
        // 5 standard errors (false alarm 6e-7 per channel), plus the texel
        // store's rounding to half floats (at most 2^-11 of each texel, so
        // of their mean).
        const double bound = 5.0 * face.standardError[c] + std::ldexp(expected[c], -11);
        EXPECT_NEAR(face.mean[c], expected[c], bound)
            << "channel " << c << ": " << face.area << " pixels of face, standard error "
            << face.standardError[c];
        // Power: the texels' mean without sRGB decoding is far outside it.
        EXPECT_GT(std::abs(face.mean[c] - undecoded[c]), 4.0 * bound) << "channel " << c;
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

// ---------------------------------------------------------------------------
// TextureTransformTest: the arrows point at "Correct"
// ---------------------------------------------------------------------------
//
// The model (KhronosGroup glTF-Sample-Models) is six unit quads. The top row
// shows the top-left quarter of UV.png (a yellow "not supported" sign)
// shifted by an offset of (0.5, 0), (0, 0.5) and (0.5, 0.5): a correct
// transform shows the green U, the blue V and the cyan UV quarter. The bottom
// row shows Arrow.png rotated (pi / 8), scaled (1.5) and all three together;
// small squares in front of each quad mark where the arrow's tip lands: the
// green "Correct" square where KHR_texture_transform puts it, the yellow "Not
// Supported" one where it lands without the transform, the red "Error" one
// where a rotation in the wrong sense puts it, each a little ahead of the
// tip. The squares are geometry, drawn whatever the transform does; what the
// transform moves is the arrow. So the test reads each arrow off the film
// (its black pixels: their axis, the head and the tip) and asks which square
// the arrow's line passes through just ahead of its tip: it must be Correct.
// The squares' places come from the loaded scene and the camera, not from
// numbers written here.

const char* const TRANSFORM_MODEL = "glTF2/textureTransform/TextureTransformTest.gltf";

// A quad or marker of the model on the film: the projected bounds of its
// mesh, in pixels.
struct Rect {
    double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
    double width() const { return x1 - x0; }
    glm::dvec2 centre() const { return {(x0 + x1) / 2, (y0 + y1) / 2}; }
};

// Each mesh's rectangle, by its material's name (every mesh of the model has
// its own material but the markers, which share three).
std::vector<std::pair<std::string, Rect>> layout(const scene::Scene& s, uint32_t width,
                                                 uint32_t height) {
    const shared::Camera camera = scene::makeGpuCamera(s.camera, width, height);
    std::vector<std::pair<std::string, Rect>> out;
    for (const scene::Mesh& m : s.meshes) {
        Rect r;
        for (const glm::vec3& p : m.positions) {
            const glm::dvec2 f = test::project(camera, glm::dvec3(p));
            r.x0 = std::min(r.x0, f.x);
            r.y0 = std::min(r.y0, f.y);
            r.x1 = std::max(r.x1, f.x);
            r.y1 = std::max(r.y1, f.y);
        }
        out.emplace_back(s.materials.at(m.material).name, r);
    }
    return out;
}

// Whole pixels inside `r` shrunk by `margin` pixels on each side.
template <class F>
void forPixelsIn(const Rect& r, double margin, uint32_t width, uint32_t height, F&& f) {
    const int x0 = std::max(0, int(std::ceil(r.x0 + margin)));
    const int x1 = std::min(int(width), int(std::floor(r.x1 - margin)));
    const int y0 = std::max(0, int(std::ceil(r.y0 + margin)));
    const int y1 = std::min(int(height), int(std::floor(r.y1 - margin)));
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) f(uint32_t(x), uint32_t(y));
}

// The arrow's black: every channel below 0.1. The arrow's texels are 0, so
// its pixels are exactly 0 but at its edges; the white around it renders at
// ~0.8 with noise and never that dark at 4 spp, and each square's colour has
// a channel above 0.5.
bool dark(const glm::vec3& p) {
    return p.x < 0.1f && p.y < 0.1f && p.z < 0.1f;
}

bool inside(const Rect& r, double x, double y, double margin) {
    return x > r.x0 - margin && x < r.x1 + margin && y > r.y0 - margin && y < r.y1 + margin;
}

// An arrow read off the film: its dark pixels inside `quad` (not under a
// marker), their principal axis, the end where they spread wider across the
// axis (the head) and the tip, the farthest pixel along the axis there.
struct Arrow {
    size_t pixels = 0;
    glm::dvec2 tip{0.0}, direction{0.0};  // direction: unit, from tail to head
};

Arrow readArrow(const image::Image& image, const Rect& quad, const std::vector<Rect>& markers) {
    std::vector<glm::dvec2> points;
    forPixelsIn(quad, 1.0, image.width, image.height, [&](uint32_t x, uint32_t y) {
        const glm::dvec2 centre(x + 0.5, y + 0.5);
        for (const Rect& m : markers)
            if (inside(m, centre.x, centre.y, 1.0)) return;
        if (dark(image.at(x, y))) points.push_back(centre);
    });
    Arrow arrow;
    arrow.pixels = points.size();
    if (points.size() < 20) return arrow;
    glm::dvec2 mean(0.0);
    for (const glm::dvec2& p : points) mean += p;
    mean /= double(points.size());
    double sxx = 0, sxy = 0, syy = 0;
    for (const glm::dvec2& p : points) {
        const glm::dvec2 d = p - mean;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    // The major axis of the 2 x 2 covariance.
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    glm::dvec2 axis(std::cos(angle), std::sin(angle));
    const glm::dvec2 across(-axis.y, axis.x);
    double lo = 1e30, hi = -1e30;
    for (const glm::dvec2& p : points) {
        lo = std::min(lo, glm::dot(p - mean, axis));
        hi = std::max(hi, glm::dot(p - mean, axis));
    }
    // Spread across the axis within the last quarter of each end.
    auto spread = [&](bool high) {
        double a = 1e30, b = -1e30;
        for (const glm::dvec2& p : points) {
            const double t = glm::dot(p - mean, axis);
            if (high ? t < hi - 0.25 * (hi - lo) : t > lo + 0.25 * (hi - lo)) continue;
            a = std::min(a, glm::dot(p - mean, across));
            b = std::max(b, glm::dot(p - mean, across));
        }
        return b - a;
    };
    if (spread(false) > spread(true)) {
        axis = -axis;
        const double oldLo = lo;
        lo = -hi;
        hi = -oldLo;
    }
    // The tip: the mean of the pixels within a pixel of the head's end.
    glm::dvec2 tip(0.0);
    size_t n = 0;
    for (const glm::dvec2& p : points) {
        if (glm::dot(p - mean, axis) <= hi - 1.0) continue;
        tip += p;
        ++n;
    }
    arrow.tip = tip / double(n);
    arrow.direction = axis;
    return arrow;
}

struct TransformVerdict {
    std::vector<std::string>
        problems;  // empty: every arrow points at Correct, every offset shows its quarter
};

TransformVerdict judgeTransformTest(const fs::path& file, const fs::path& outputDir) {
    constexpr uint32_t W = 320, H = 240;
    TransformVerdict verdict;
    const scene::Scene s = loadQuiet(file);
    const test::Render r = test::renderOnWhiteSky(file, W, H, 4, outputDir);
    if (r.image.width != W) {
        verdict.problems.push_back("no render");
        return verdict;
    }
    const auto rects = layout(s, W, H);
    std::map<std::string, int> count;
    for (const auto& [name, rect] : rects) ++count[name];
    const std::map<std::string, int> model = {
        {"Offset U", 1}, {"Offset V", 1}, {"Offset UV", 1}, {"Rotation", 1},    {"Scale", 1},
        {"All", 1},      {"Correct", 3},  {"Error", 1},     {"NotSupported", 2}};
    if (count != model) verdict.problems.push_back("the scene is not the model this test knows");

    // The top row: each quad's mean colour is nearest its quarter of UV.png.
    const test::Texels uv = test::readTexels(file.parent_path() / "UV.png");
    const int hw = uv.width / 2, hh = uv.height / 2;
    const std::vector<std::pair<std::string, glm::dvec3>> quarters = {
        {"not supported (top left)", test::meanTexel(uv, 0, 0, hw, hh, test::srgbToLinear)},
        {"U (top right)", test::meanTexel(uv, hw, 0, uv.width, hh, test::srgbToLinear)},
        {"V (bottom left)", test::meanTexel(uv, 0, hh, hw, uv.height, test::srgbToLinear)},
        {"UV (bottom right)",
         test::meanTexel(uv, hw, hh, uv.width, uv.height, test::srgbToLinear)}};
    const std::map<std::string, size_t> expectedQuarter = {
        {"Offset U", 1}, {"Offset V", 2}, {"Offset UV", 3}};
    for (const auto& [name, rect] : rects) {
        const auto expected = expectedQuarter.find(name);
        if (expected == expectedQuarter.end()) continue;
        glm::dvec3 sum(0.0);
        size_t n = 0;
        forPixelsIn(rect, 1.0, W, H, [&](uint32_t x, uint32_t y) {
            sum += glm::dvec3(r.image.at(x, y));
            ++n;
        });
        const glm::dvec3 mean = sum / double(n);
        size_t nearest = 0;
        for (size_t q = 1; q < quarters.size(); ++q)
            if (glm::length(mean - quarters[q].second) <
                glm::length(mean - quarters[nearest].second))
                nearest = q;
        if (nearest != expected->second)
            verdict.problems.push_back(name + " shows the " + quarters[nearest].first +
                                       " quarter, not " + quarters[expected->second].first);
    }

    // The bottom row: each arrow's line from its tip passes through a square
    // ahead of it, and the nearest such square is Correct.
    std::vector<std::pair<std::string, Rect>> markers;
    std::vector<Rect> markerRects;
    for (const auto& [name, rect] : rects)
        if (name == "Correct" || name == "NotSupported" || name == "Error") {
            markers.emplace_back(name, rect);
            markerRects.push_back(rect);
        }
    for (const auto& [name, quad] : rects) {
        if (name != "Rotation" && name != "Scale" && name != "All") continue;
        const Arrow arrow = readArrow(r.image, quad, markerRects);
        if (arrow.pixels < 20) {
            verdict.problems.push_back(name + ": no arrow on the film");
            continue;
        }
        // Among the quad's own squares (those nearer its centre than any
        // other quad's), the one the arrow's line passes through (less than
        // a side off it: the square's corners are 0.71 sides from its centre)
        // just ahead of the tip (from half a side behind to 3 sides ahead),
        // the nearest to the line if several.
        std::string pointedAt = "nothing", measured;
        double best = 1e30;
        for (const auto& [markerName, m] : markers) {
            const glm::dvec2 c = m.centre();
            bool own = true;
            for (const auto& [otherName, other] : rects)
                if ((otherName == "Rotation" || otherName == "Scale" || otherName == "All") &&
                    glm::length(c - other.centre()) < glm::length(c - quad.centre()))
                    own = false;
            if (!own) continue;
            const glm::dvec2 v = c - arrow.tip;
            const double along = glm::dot(v, arrow.direction) / m.width();
            const double off =
                glm::length(v - glm::dot(v, arrow.direction) * arrow.direction) / m.width();
            measured += fmt::format(" {}: {:.2f} sides ahead, {:.2f} off;", markerName, along, off);
            if (along > -0.5 && along < 3.0 && off < 1.0 && off < best) {
                best = off;
                pointedAt = markerName;
            }
        }
        if (pointedAt != "Correct")
            verdict.problems.push_back(name + ": the arrow points at " + pointedAt +
                                       ", not Correct (" + measured +
                                       " from the tip along the arrow)");
    }
    return verdict;
}

TEST(TextureTransformTest, EveryArrowPointsAtCorrect) {
    SKIP_WITHOUT_PACKAGE();
    const test::TempDir dir;
    const TransformVerdict v = judgeTransformTest(MODELS / TRANSFORM_MODEL, dir.path());
    for (const std::string& p : v.problems) ADD_FAILURE() << p;
}

// The same judgement rejects the model as a renderer without the transform,
// or with rotations the wrong way round, would draw it: the files rewritten
// so (in a temporary folder, with copies of the model's images).
TEST(TextureTransformTest, WrongTransformsAreRejected) {
    SKIP_WITHOUT_PACKAGE();
    const fs::path source = MODELS / TRANSFORM_MODEL;
    std::ifstream in(source);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const test::TempDir dir;
    for (const char* name : {"Arrow.png", "Correct.png", "Error.png", "NotSupported.png", "UV.png",
                             "TextureTransformTest.bin"})
        fs::copy_file(source.parent_path() / name, dir / name);
    auto replaced = [](std::string t, const std::string& from, const std::string& to) {
        size_t count = 0;
        for (size_t at = t.find(from); at != std::string::npos;
             at = t.find(from, at + to.size()), ++count)
            t.replace(at, from.size(), to);
        EXPECT_GT(count, 0u) << from;
        return t;
    };
    // Without the extension (a renderer that ignores it), and with every
    // rotation negated (one that turns the wrong way).
    const fs::path ignored = dir.write(
        "ignored.gltf", replaced(text, "\"KHR_texture_transform\": {", "\"VKPATH_ignored\": {"));
    const fs::path reversed =
        dir.write("reversed.gltf", replaced(text, "\"rotation\": 0.", "\"rotation\": -0."));
    auto says = [](const TransformVerdict& v, const std::string& what) {
        for (const std::string& p : v.problems)
            if (p.find(what) != std::string::npos) return true;
        return false;
    };
    const TransformVerdict without = judgeTransformTest(ignored, dir.path());
    EXPECT_TRUE(says(without, "Offset U shows the not supported (top left) quarter"));
    EXPECT_TRUE(says(without, "Offset V shows the not supported (top left) quarter"));
    EXPECT_TRUE(says(without, "Offset UV shows the not supported (top left) quarter"));
    EXPECT_TRUE(says(without, "Rotation: the arrow points at NotSupported"));
    EXPECT_TRUE(says(without, "Scale: the arrow points at NotSupported"));
    EXPECT_TRUE(says(without, "All: the arrow points at nothing"));
    const TransformVerdict backwards = judgeTransformTest(reversed, dir.path());
    EXPECT_TRUE(says(backwards, "Rotation: the arrow points at Error"));
    EXPECT_TRUE(says(backwards, "All: the arrow points at nothing"));
    EXPECT_EQ(backwards.problems.size(), 2u) << "the offsets and the scale are still right";
}

}  // namespace
