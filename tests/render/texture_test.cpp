// Textures and vertex colours (shared/texture.h, path_tracer.h textureLookup
// and materialAt): the lookup against hand-computed texels for each wrap mode,
// both filters, the transform and sRGB decoding, through the CPU reference's
// view of the scene tables (the same code the kernels run), then whole
// renders on the GPU where every pixel's value is known exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "reference/path_tracer_view.h"
#include "reference/reference_renderer.h"
#include "support/binding_limit.h"
#include "support/test_context.h"
#include "wavefront/renderer.h"
#include "wavefront/texture_tables.h"

namespace {

using namespace vkpath;

// 16-bit normalised from an 8-bit value, as the loader widens 8-bit images.
uint16_t widen(int v8) {
    return uint16_t(v8 * 257);
}

// A 4 x 2 image: texel (i, j) has red 60 i + 10, green 100 j + 20 (8-bit,
// sRGB-encoded), blue 255, alpha 255.
scene::TextureImage testImage() {
    scene::TextureImage image;
    image.name = "test";
    image.width = 4;
    image.height = 2;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i)
            image.texels.push_back(
                glm::u16vec4(widen(60 * i + 10), widen(100 * j + 20), widen(255), widen(255)));
    return image;
}

// What texel (i, j) holds once decoded (linear, as the store keeps it).
glm::dvec2 texelValue(int i, int j) {
    return {wavefront::srgbToLinear((60 * i + 10) / 255.0),
            wavefront::srgbToLinear((100 * j + 20) / 255.0)};
}

// A unit square in z = 0 facing +z, u along +x, v along -y (glTF: v down), so
// the camera at +z sees the image upright.
scene::Mesh texturedSquare() {
    scene::Mesh m;
    m.positions = {{-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}};
    m.texcoords0 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

scene::Scene texturedScene(scene::TextureWrap wrap, bool nearest, scene::TextureRef ref = {}) {
    scene::Scene s;
    s.images.push_back(testImage());
    s.textures.push_back({0, wrap, wrap, nearest});
    scene::Material m;
    ref.texture = 0;
    m.baseColorTexture = ref;
    s.materials.push_back(m);
    s.meshes.push_back(texturedSquare());
    s.camera.position = {0, 0, 2};
    s.camera.target = {0, 0, 0};
    return s;
}

struct Lookup {
    wavefront::SceneTables tables;
    shared::PathTracerView view;

    explicit Lookup(const scene::Scene& s)
        : tables(wavefront::buildSceneTables(s)),
          view(tables, wavefront::renderSceneInfo(tables, {})) {}
    glm::dvec2 at(float u, float v) const {
        const glm::vec4 value = view.textureLookup(tables.textures.textures.at(0), glm::vec2(u, v));
        return {value.x, value.y};
    }
};

// Half floats keep 11 significant bits: 2^-11 relative.
void expectNear(glm::dvec2 got, glm::dvec2 expected, const char* what) {
    for (int c = 0; c < 2; ++c)
        EXPECT_NEAR(got[c], expected[c], 5e-4 * std::abs(expected[c]) + 1e-7)
            << what << " channel " << c;
}

TEST(TextureLookup, SrgbTexelsAreDecodedToLinear) {
    EXPECT_NEAR(wavefront::srgbToLinear(0.5), 0.214041, 1e-6);  // IEC 61966-2-1
    EXPECT_NEAR(wavefront::srgbToLinear(0.04), 0.04 / 12.92, 1e-12);
    const Lookup l(texturedScene(scene::TextureWrap::Repeat, true));
    ASSERT_EQ(l.tables.textures.texels.size(), 8u);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i)
            expectNear(l.at((i + 0.5f) / 4, (j + 0.5f) / 2), texelValue(i, j), "centre");
}

TEST(TextureLookup, NearestTakesTheTexelThePointLiesIn) {
    const Lookup l(texturedScene(scene::TextureWrap::Repeat, true));
    expectNear(l.at(0.01f, 0.01f), texelValue(0, 0), "top-left corner");
    expectNear(l.at(0.249f, 0.499f), texelValue(0, 0), "just inside texel (0, 0)");
    expectNear(l.at(0.251f, 0.501f), texelValue(1, 1), "just past its far corner");
    expectNear(l.at(0.99f, 0.99f), texelValue(3, 1), "bottom-right corner");
}

TEST(TextureLookup, BilinearWeighsTheFourSurroundingCentres) {
    const Lookup l(texturedScene(scene::TextureWrap::ClampToEdge, false));
    // Midway between the centres of texels 1 and 2 in u, on row 0's centre.
    expectNear(l.at(0.5f, 0.25f), (texelValue(1, 0) + texelValue(2, 0)) * 0.5, "midway in u");
    // A quarter of the way from the centre of (1, 0) toward (2, 1) in both.
    const double fx = 0.25, fy = 0.25;
    const glm::dvec2 expected = (1 - fy) * ((1 - fx) * texelValue(1, 0) + fx * texelValue(2, 0)) +
                                fy * ((1 - fx) * texelValue(1, 1) + fx * texelValue(2, 1));
    expectNear(l.at((1.5f + 0.25f) / 4, (0.5f + 0.25f) / 2), expected,
               "(0.25, 0.25) between four centres");
}

TEST(TextureLookup, WrapModes) {
    {
        const Lookup l(texturedScene(scene::TextureWrap::Repeat, true));
        expectNear(l.at(1.125f, 2.25f), texelValue(0, 0), "repeat past 1");
        expectNear(l.at(-0.125f, -0.25f), texelValue(3, 1), "repeat below 0");
        const Lookup b(texturedScene(scene::TextureWrap::Repeat, false));
        // At u = 0 (the left edge) bilinear filtering blends the first and last columns.
        expectNear(b.at(0.0f, 0.25f), (texelValue(0, 0) + texelValue(3, 0)) * 0.5,
                   "repeat blends across the seam");
    }
    {
        const Lookup l(texturedScene(scene::TextureWrap::ClampToEdge, true));
        expectNear(l.at(1.5f, -3.0f), texelValue(3, 0), "clamp");
        const Lookup b(texturedScene(scene::TextureWrap::ClampToEdge, false));
        expectNear(b.at(0.0f, 0.25f), texelValue(0, 0), "clamp: the edge texel alone at the edge");
    }
    {
        const Lookup l(texturedScene(scene::TextureWrap::MirroredRepeat, true));
        expectNear(l.at(1.125f, 0.25f), texelValue(3, 0),
                   "mirrored: just past 1 is the last column");
        expectNear(l.at(1.875f, 0.25f), texelValue(0, 0), "mirrored: just before 2 is the first");
        expectNear(l.at(-0.125f, 0.25f), texelValue(0, 0), "mirrored: just below 0 is the first");
        expectNear(l.at(2.125f, 0.25f), texelValue(0, 0), "mirrored: period 2");
    }
    // Coordinates far outside (and non-finite-free) stay in range.
    const Lookup l(texturedScene(scene::TextureWrap::Repeat, false));
    const glm::dvec2 far = l.at(-3.0e9f, 7.0e12f);
    EXPECT_TRUE(std::isfinite(far.x) && std::isfinite(far.y));
}

// KHR_texture_transform: uv' = T R S uv. A rotation of 90 degrees with scale
// (2, 0.5) and offset (0.25, 0.5) maps uv to (0.5 v + 0.25, -2 u + 0.5).
TEST(TextureLookup, TransformIsTranslationRotationScale) {
    scene::TextureRef ref;
    ref.offset = {0.25f, 0.5f};
    ref.rotation = float(M_PI / 2);
    ref.scale = {2.0f, 0.5f};
    const Lookup l(texturedScene(scene::TextureWrap::Repeat, true, ref));
    const shared::TextureSlot slot = l.tables.textures.slots.at(VKP_SLOT_BASE_COLOR);
    for (const glm::vec2 uv :
         {glm::vec2(0.1f, 0.2f), glm::vec2(0.7f, 0.9f), glm::vec2(-0.3f, 0.45f)}) {
        const glm::vec2 expected(0.5f * uv.y + 0.25f, -2.0f * uv.x + 0.5f);
        const glm::vec3 p(uv, 1.0f);
        EXPECT_NEAR(glm::dot(slot.transformU, p), expected.x, 1e-6f);
        EXPECT_NEAR(glm::dot(slot.transformV, p), expected.y, 1e-6f);
        const glm::vec4 value =
            l.view.textureSlotValue(VKP_SLOT_BASE_COLOR, glm::vec4(uv, 0.0f, 0.0f));
        expectNear({value.x, value.y}, l.at(expected.x, expected.y),
                   "slot value at the transformed uv");
    }
}

// A square whose emission is the texture (nearest), filling the film: every
// pixel that lies inside one texel's footprint shows exactly that texel, on
// the GPU and the CPU, upright (texel row 0 at the top of the image).
TEST(TexturedRender, EmissiveTextureIsSeenTexelForTexel) {
    scene::Scene s = texturedScene(scene::TextureWrap::Repeat, true);
    scene::Material& m = s.materials[0];
    m.reflectance = glm::vec3(0.0f);
    m.emission = glm::vec3(1.0f);
    m.emissiveTexture = m.baseColorTexture;
    m.baseColorTexture = {};
    s.camera.xfovDegrees =
        float(2 * std::atan(1.0 / 2.0) * 180 / M_PI);  // the square exactly fills the width
    wavefront::RenderSettings settings;
    settings.width = 64;
    settings.height = 64;
    settings.samplesPerPixel = 4;
    settings.maxDepth = 2;
    for (bool cpu : {false, true}) {
        SCOPED_TRACE(cpu ? "CPU reference" : "GPU");
        const auto r = cpu ? reference::ReferenceRenderer(s, settings).render()
                           : wavefront::GpuRenderer(test::context(), s, settings).render();
        int checked = 0;
        for (uint32_t y = 0; y < 64; ++y)
            for (uint32_t x = 0; x < 64; ++x) {
                // Texel columns are 16 pixels wide; rows (two, 32 pixels each) start at y = 0.
                if (x % 16 == 0 || x % 16 == 15 || y % 32 == 0 || y % 32 == 31) continue;
                const glm::dvec2 expected = texelValue(int(x / 16), int(y / 32));
                const glm::vec3 got = r.image.pixels[y * 64 + x];
                expectNear({got.x, got.y}, expected, "pixel");
                ASSERT_NEAR(got.z, 1.0f, 1e-3f);
                ++checked;
            }
        EXPECT_EQ(checked, 4 * 2 * 14 * 30);
    }
}

// Vertex colours multiply the base colour: a white diffuse square whose
// vertices are coloured c, lit by a directional light along its normal,
// reflects rho c / pi x E everywhere (c the same at all four vertices), and
// red rising from left to right when only the right vertices are red.
TEST(TexturedRender, VertexColoursMultiplyTheBaseColour) {
    scene::Scene s;
    scene::Material white;
    white.reflectance = glm::vec3(0.5f);
    s.materials.push_back(white);
    scene::Mesh square = texturedSquare();
    const glm::vec4 c(0.2f, 0.6f, 1.0f, 1.0f);
    square.colors = {c, c, c, c};
    s.meshes.push_back(square);
    s.camera.position = {0, 0, 2};
    s.camera.target = {0, 0, 0};
    s.camera.xfovDegrees = 30.0f;
    s.directionalLights.push_back({glm::vec3(0, 0, -1), glm::vec3(2.0f)});
    wavefront::RenderSettings settings;
    settings.width = settings.height = 16;
    settings.samplesPerPixel = 2;
    const auto r = wavefront::GpuRenderer(test::context(), s, settings).render();
    for (const glm::vec3& p : r.image.pixels)
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(p[k], 0.5 * c[k] / M_PI * 2.0, 1e-5);

    s.meshes[0].colors = {
        {0, 1, 1, 1}, {0, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1, 1}};  // left: cyan, right: white
    const auto g = wavefront::GpuRenderer(test::context(), s, settings).render();
    for (uint32_t y = 0; y < 16; ++y)
        for (uint32_t x = 1; x < 16; ++x)
            ASSERT_GT(g.image.pixels[y * 16 + x].x, g.image.pixels[y * 16 + x - 1].x);
    EXPECT_NEAR(g.image.pixels[8 * 16].y, 0.5 / M_PI * 2.0, 1e-5);  // green is white everywhere
}

// The vertex attributes and the texel store read by buffer device address
// (scenes beyond a binding; here the limit is lowered) give the image the
// bound buffers give, bit for bit: a textured, vertex-coloured, smooth-shaded
// square.
TEST(TexturedRender, ByAddressEqualsBound) {
    scene::Scene s = texturedScene(scene::TextureWrap::MirroredRepeat, false);
    scene::Mesh& m = s.meshes[0];
    m.colors = {{1, 0.5f, 1, 1}, {1, 1, 1, 1}, {0.5f, 1, 1, 1}, {1, 1, 1, 1}};
    m.normals = {
        glm::normalize(glm::vec3(-0.3f, 0.3f, 1)), glm::normalize(glm::vec3(-0.3f, -0.3f, 1)),
        glm::normalize(glm::vec3(0.3f, -0.3f, 1)), glm::normalize(glm::vec3(0.3f, 0.3f, 1))};
    s.directionalLights.push_back({glm::normalize(glm::vec3(0.2f, -0.1f, -1)), glm::vec3(2.0f)});
    // A second square hidden behind the first, so that the primitives (4 x 48
    // bytes) outgrow the lowered binding below while one material (112) fits.
    scene::Mesh hidden = texturedSquare();
    for (glm::vec3& p : hidden.positions) p.z = -3.0f;
    s.meshes.push_back(hidden);
    wavefront::RenderSettings settings;
    settings.width = settings.height = 16;
    settings.samplesPerPixel = 2;
    const auto bound = wavefront::GpuRenderer(test::context(), s, settings).render();
    const test::BindingLimit lowered(
        sizeof(shared::Material));  // one material fits (materials stay bound)
    wavefront::GpuRenderer addressed(test::context(), s, settings);
    ASSERT_TRUE(addressed.scene().byAddress);
    const auto r = addressed.render();
    for (size_t i = 0; i < r.image.pixels.size(); ++i)
        ASSERT_EQ(r.image.pixels[i], bound.image.pixels[i]) << i;
}

}  // namespace
