// Normal maps (shared/path_tracer.h normalMapNormal, tangents from the scene
// or host/scene/tangents) against analytic radiance: a diffuse plane of
// albedo rho under a directional light of irradiance E, whose normal map
// gives the shading normal n, reflects rho / pi E (n . l) wherever nothing
// else lights it (black sky, a plane cannot see itself), so every camera
// ray's estimate is exact up to float rounding, as in
// shading_normals_test.cpp. The expected normals are computed here from the
// texels as the texture store keeps them (16-bit values as half floats).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <glm/gtc/packing.hpp>
#include <string>

#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "support/binding_limit.h"
#include "support/test_context.h"
#include "wavefront/kernel_features.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

constexpr double PI = 3.14159265358979323846;
constexpr float ALBEDO = 0.5f;
const glm::dvec3 IRRADIANCE(1.0, 2.0, 3.0);
constexpr uint32_t SIZE = 64;

// A tangent-space normal component in [-1, 1] as a 16-bit texel value.
uint16_t encode(double c) {
    return uint16_t(std::lround((c + 1.0) / 2.0 * 65535.0));
}

// What the shading code reads for it: the value as the store keeps it (a
// half float, wavefront/texture_tables), then 2 x - 1.
double decode(uint16_t v) {
    const float stored =
        glm::unpackHalf2x16(glm::packHalf2x16(glm::vec2(float(v / 65535.0), 0.0f))).x;
    return 2.0 * double(stored) - 1.0;
}

// A normal map of width x height texels, texel (i, j) holding normals[j * width + i].
scene::TextureImage normalMap(uint32_t width, uint32_t height,
                              const std::vector<glm::dvec3>& normals) {
    scene::TextureImage image;
    image.name = "normals";
    image.width = width;
    image.height = height;
    for (const glm::dvec3& n : normals)
        image.texels.emplace_back(encode(n.x), encode(n.y), encode(n.z), 65535);
    return image;
}

// The unit tangent-space normal the renderer makes of a texel: decoded,
// x and y times the normal scale, normalised (glTF 2.0, 3.9.3).
glm::dvec3 mappedNormal(const glm::u16vec4& texel, double scale) {
    return glm::normalize(
        glm::dvec3(scale * decode(texel.x), scale * decode(texel.y), decode(texel.z)));
}

struct PlaneOptions {
    bool mirrored = false;                   // u runs along -x instead of +x
    bool givenTangents = false;              // TANGENT in the mesh, else generated
    glm::dvec3 vertexNormal{0.0, 1.0, 0.0};  // the same at every vertex
    float scale = 1.0f;                      // normalTexture.scale
    bool nearest = true;
};

// The square [-1, 1]^2 in y = 0 facing +y, seen straight down from y = 2
// with the camera's up along -z so that it exactly fills the film, upright:
// u = (x + 1) / 2 (mirrored: (1 - x) / 2) and v = (z + 1) / 2, v down the
// image as in glTF. Lit by a directional light from `toLight`.
scene::Scene normalMappedPlane(const scene::TextureImage& map, const PlaneOptions& o,
                               glm::dvec3 toLight) {
    scene::Scene s;
    s.images.push_back(map);
    s.textures.push_back(
        {0, scene::TextureWrap::ClampToEdge, scene::TextureWrap::ClampToEdge, o.nearest});
    scene::Material m;
    m.reflectance = glm::vec3(ALBEDO);
    m.normalTexture.texture = 0;
    m.normalScale = o.scale;
    s.materials.push_back(m);
    scene::Mesh plane;
    plane.positions = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}};
    for (const glm::vec3& p : plane.positions) {
        plane.texcoords0.emplace_back(o.mirrored ? (1 - p.x) / 2 : (p.x + 1) / 2, (p.z + 1) / 2);
        plane.normals.push_back(glm::vec3(glm::normalize(o.vertexNormal)));
        if (o.givenTangents)
            plane.tangents.push_back(o.mirrored ? glm::vec4(-1, 0, 0, -1) : glm::vec4(1, 0, 0, 1));
    }
    plane.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.meshes.push_back(plane);
    s.camera.position = {0, 2, 0};
    s.camera.target = {0, 0, 0};
    s.camera.up = {0, 0, -1};
    s.camera.xfovDegrees = float(2 * std::atan(0.5) * 180 / PI);
    s.directionalLights.push_back({glm::vec3(-glm::normalize(toLight)), glm::vec3(IRRADIANCE)});
    return s;
}

// The world-space shading normal of tangent-space normal `n` on the plane:
// N the vertex normal, T the u direction (+x, or -x mirrored) made
// orthogonal to N, and B = w (N x T) with w = -1 when mirrored, which
// points up the image (-z) either way.
glm::dvec3 worldNormal(glm::dvec3 n, const PlaneOptions& o) {
    const glm::dvec3 N = glm::normalize(o.vertexNormal);
    const glm::dvec3 u(o.mirrored ? -1.0 : 1.0, 0.0, 0.0);
    const glm::dvec3 T = glm::normalize(u - glm::dot(N, u) * N);
    const glm::dvec3 B = (o.mirrored ? -1.0 : 1.0) * glm::cross(N, T);
    return glm::normalize(n.x * T + n.y * B + n.z * N);
}

glm::dvec3 radiance(glm::dvec3 shadingNormal, glm::dvec3 toLight) {
    return ALBEDO / PI * IRRADIANCE *
           std::max(0.0, glm::dot(shadingNormal, glm::normalize(toLight)));
}

wavefront::RenderSettings settings(uint32_t size, uint32_t spp) {
    wavefront::RenderSettings s;
    s.width = s.height = size;
    s.samplesPerPixel = spp;
    s.maxDepth = 4;
    return s;
}

wavefront::RenderResult render(const scene::Scene& s, bool cpu, uint32_t size = SIZE,
                               uint32_t spp = 2) {
    return cpu ? reference::ReferenceRenderer(s, settings(size, spp)).render()
               : wavefront::GpuRenderer(test::context(), s, settings(size, spp)).render();
}

// Within float rounding: the light is a delta and the surface diffuse, so
// there is no noise (1e-5 relative, as PunctualLights.* and
// ShadingNormals.* measure).
void expectRadiance(const glm::vec3& got, const glm::dvec3& expected, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(got[c], expected[c], 1e-5 * expected[c]) << what << " channel " << c;
}

// One texel tilting the normal by 19.5 degrees toward +u and up the image:
// the whole plane shades with the mapped normal, for tangents generated or
// given, the texture mirrored or not (w = -1), normalTexture.scale 0.6, and
// vertex normals tilted by 10 degrees (the tangent is made orthogonal to
// them). The camera's field of view is narrowed to 30 degrees, so that no
// view direction reflects below the surface about the mapped normal
// (shared/bsdf.h would adapt it). The light is placed so that the mapped
// normal's cosine differs from the vertex normal's by more than 15%, and
// from what a bitangent of the wrong sign would give by more than 50%: the
// test sees the map, and its orientation.
TEST(NormalMaps, ConstantTiltShadesWithTheMappedNormal) {
    const scene::TextureImage map = normalMap(1, 1, {glm::normalize(glm::dvec3(0.25, 0.25, 1.0))});
    const glm::dvec3 toLight(0.2, 1.0, -1.2);
    struct Case {
        const char* name;
        bool mirrored, given;
        float scale;
        glm::dvec3 vertexNormal;
    };
    const glm::dvec3 up(0, 1, 0), tilted(std::sin(10 * PI / 180), std::cos(10 * PI / 180), 0.0);
    for (const Case& c :
         {Case{"generated tangents", false, false, 1.0f, up},
          Case{"given tangents", false, true, 1.0f, up},
          Case{"mirrored, generated tangents", true, false, 1.0f, up},
          Case{"mirrored, given tangents", true, true, 1.0f, up},
          Case{"scale 0.6", false, false, 0.6f, up},
          Case{"tilted vertex normals, generated tangents", false, false, 1.0f, tilted},
          Case{"tilted vertex normals, given tangents, mirrored", true, true, 1.0f, tilted}}) {
        PlaneOptions o;
        o.mirrored = c.mirrored;
        o.givenTangents = c.given;
        o.scale = c.scale;
        o.vertexNormal = c.vertexNormal;
        const glm::dvec3 n = mappedNormal(map.texels[0], c.scale);
        const glm::dvec3 expected = radiance(worldNormal(n, o), toLight);
        const glm::dvec3 unmapped = radiance(glm::normalize(c.vertexNormal), toLight);
        const glm::dvec3 wrongB = radiance(worldNormal(glm::dvec3(n.x, -n.y, n.z), o), toLight);
        ASSERT_GT(std::abs(expected.x / unmapped.x - 1), c.scale == 1.0f ? 0.15 : 0.08) << c.name;
        ASSERT_GT(std::abs(expected.x / wrongB.x - 1), c.scale == 1.0f ? 0.5 : 0.3) << c.name;
        scene::Scene s = normalMappedPlane(map, o, toLight);
        s.camera.xfovDegrees = 30.0f;
        for (const bool cpu : {false, true}) {
            SCOPED_TRACE(std::string(cpu ? "CPU, " : "GPU, ") + c.name);
            const auto r = render(s, cpu, SIZE / 2, 2);
            EXPECT_EQ(r.nonFiniteSamples, 0u);
            for (const glm::vec3& p : r.image.pixels) {
                expectRadiance(p, expected, c.name);
                if (HasFatalFailure()) return;
            }
        }
    }
}

// A normal map of a known gradient: texel (i, j) of a 4 x 2 map holds the
// normal of the height field h = 0.1 (X^2 + Y^2) at its centre, X = i - 1.5
// rightward and Y = 0.5 - j up the image, n = normalize(-dh/dX, -dh/dY, 1)
// (tilts up to 17.5 degrees, every texel a different direction). Nearest
// filtering, the plane filling the film exactly (texel columns 16 pixels
// wide, rows 32 high): every pixel inside a texel's footprint shades with
// that texel's normal, mirrored texture or not, GPU and CPU. Mirrored, the
// image is seen from behind: column i lands where column 3 - i would.
TEST(NormalMaps, GradientMapShadesEachTexelWithItsNormal) {
    std::vector<glm::dvec3> normals;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i)
            normals.push_back(glm::normalize(glm::dvec3(-0.2 * (i - 1.5), -0.2 * (0.5 - j), 1)));
    const scene::TextureImage map = normalMap(4, 2, normals);
    const glm::dvec3 toLight(0.2, 1.0, -1.2);
    for (const bool mirrored : {false, true}) {
        PlaneOptions o;
        o.mirrored = mirrored;
        const scene::Scene s = normalMappedPlane(map, o, toLight);
        for (const bool cpu : {false, true}) {
            SCOPED_TRACE(std::string(cpu ? "CPU" : "GPU") + (mirrored ? ", mirrored" : ""));
            const auto r = render(s, cpu);
            EXPECT_EQ(r.nonFiniteSamples, 0u);
            int checked = 0;
            for (uint32_t y = 0; y < SIZE; ++y)
                for (uint32_t x = 0; x < SIZE; ++x) {
                    if (x % 16 == 0 || x % 16 == 15 || y % 32 == 0 || y % 32 == 31) continue;
                    const int i = mirrored ? 3 - int(x / 16) : int(x / 16), j = int(y / 32);
                    const glm::dvec3 n =
                        worldNormal(mappedNormal(map.texels[size_t(j * 4 + i)], 1.0), o);
                    expectRadiance(r.image.pixels[y * SIZE + x], radiance(n, toLight),
                                   "pixel " + std::to_string(x) + ", " + std::to_string(y));
                    if (HasFatalFailure()) return;
                    ++checked;
                }
            EXPECT_EQ(checked, 4 * 2 * 14 * 30);
        }
    }
}

// Only meshes whose material has a normal map get tangents (and their
// triangles the bit), and the kernels the normal-map code; without a map
// there is no tangent array and no feature bit.
TEST(NormalMaps, TangentsOnlyWhereAMaterialHasAMap) {
    const scene::TextureImage map = normalMap(1, 1, {glm::dvec3(0, 0, 1)});
    scene::Scene s = normalMappedPlane(map, {}, {0, 1, 0});
    scene::Mesh unmapped = s.meshes[0];
    for (glm::vec3& p : unmapped.positions) p.y -= 1.0f;
    unmapped.material = 1;
    scene::Material plain;
    plain.baseColorTexture.texture = 0;  // textured, so the mesh keeps its texture coordinates
    s.materials.push_back(plain);
    s.meshes.push_back(unmapped);
    const wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    EXPECT_EQ(tables.surface.vertexTangents.size(), 8u);
    ASSERT_EQ(tables.surface.triangleVertices.size(), 4u);
    for (int t = 0; t < 4; ++t)
        EXPECT_EQ((tables.surface.triangleVertices[t].attributes & VKP_TRIANGLE_TANGENTS) != 0,
                  t < 2)
            << t;
    EXPECT_NE(wavefront::sceneFeatures(tables) & VKP_FEATURE_NORMAL_MAPS, 0u);

    s.materials[0].normalTexture = {};
    const wavefront::SceneTables without = wavefront::buildSceneTables(s);
    EXPECT_TRUE(without.surface.vertexTangents.empty());
    EXPECT_EQ(without.surface.attributes & VKP_TRIANGLE_TANGENTS, 0u);
    EXPECT_EQ(wavefront::sceneFeatures(without) & VKP_FEATURE_NORMAL_MAPS, 0u);

    // A map whose texture coordinates the mesh lacks has nothing to be read at.
    s.materials[0].normalTexture.texture = 0;
    s.materials[0].normalTexture.texCoord = 1;
    EXPECT_TRUE(wavefront::buildSceneTables(s).surface.vertexTangents.empty());
}

// Tangents read by buffer device address (scenes beyond a binding; here the
// limit is lowered) give the image the bound buffers give, bit for bit, on a
// plane whose mirrored texture splits vertices (u = |x|) under a bilinear
// gradient map.
TEST(NormalMaps, ByAddressEqualsBound) {
    std::vector<glm::dvec3> normals;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i)
            normals.push_back(glm::normalize(glm::dvec3(0.1 * i, -0.1 * j, 1)));
    PlaneOptions o;
    o.nearest = false;
    scene::Scene s = normalMappedPlane(normalMap(4, 2, normals), o, {0.2, 1.0, -1.2});
    scene::Mesh& m = s.meshes[0];
    m.positions.insert(m.positions.end(), {{0, 0, -1}, {0, 0, 1}});
    m.normals.insert(m.normals.end(), 2, glm::vec3(0, 1, 0));
    m.texcoords0.clear();
    for (const glm::vec3& p : m.positions) m.texcoords0.emplace_back(std::abs(p.x), (p.z + 1) / 2);
    m.triangles = {{0, 1, 5}, {0, 5, 4}, {4, 5, 2}, {4, 2, 3}};
    const wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    ASSERT_EQ(tables.surface.vertexTangents.size(), 8u) << "the two vertices at x = 0 split";
    const auto bound = wavefront::GpuRenderer(test::context(), s, settings(16, 2)).render();
    const test::BindingLimit lowered(
        sizeof(shared::Material));  // one material fits (materials stay bound)
    wavefront::GpuRenderer addressed(test::context(), s, settings(16, 2));
    ASSERT_TRUE(addressed.scene().byAddress);
    const auto r = addressed.render();
    for (size_t i = 0; i < r.image.pixels.size(); ++i)
        ASSERT_EQ(r.image.pixels[i], bound.image.pixels[i]) << i;
}

// A file made by others: the ClearCoat test model of glTF-Sample-Models
// (Debian's assimp-testmodels), whose normal maps come without TANGENT. Its
// normal-mapped meshes get generated tangents, the kernels the normal-map
// code, and a render under a white sky has no NaN or infinite sample and a
// finite, non-negative image.
TEST(NormalMaps, SampleModelWithoutTangentsRenders) {
    const std::filesystem::path file =
        "/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf";
    ASSERT_TRUE(std::filesystem::exists(file)) << file << " is missing: run tools/install-deps";
    testing::internal::CaptureStderr();  // the file's warnings (clearcoat, glossy materials...)
    scene::Scene s = scene::loadScene(file);
    testing::internal::GetCapturedStderr();
    size_t mapped = 0;
    for (const scene::Mesh& m : s.meshes)
        mapped += s.materials.at(m.material).normalTexture.present();
    EXPECT_GE(mapped, 5u);
    scene::Environment sky;
    sky.color = glm::vec3(1.0f);
    s.environment = sky;
    const wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    EXPECT_NE(wavefront::sceneFeatures(tables) & VKP_FEATURE_NORMAL_MAPS, 0u);
    wavefront::RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.samplesPerPixel = 2;
    const auto r = wavefront::GpuRenderer(test::context(), s, settings).render();
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    for (const glm::vec3& p : r.image.pixels)
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(p[c]) && p[c] >= 0.0f);
}

}  // namespace
