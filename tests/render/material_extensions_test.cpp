// glTF's material extensions in whole renders: the clear coat and the sheen
// over the metallic-roughness material (shared/metallic_roughness.h, their
// albedo per hit in shared/path/energy_compensation.h, their textures in
// shared/path/textures.h) in white furnaces, with textures that switch the
// layers off texel by texel; thin walls (glTF's transmission without a
// volume) that pass light unbent and keep the fog on both sides; an
// anisotropic highlight stretched along its direction, turned by the
// rotation or the texture alike; every execution of the path loop agreeing. Bounds: 5
// standard errors from the render's own variance AOV (false alarm 6e-7 per
// check), plus the tables' stated error where a table is read.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "image/metrics.h"
#include "image/statistics.h"
#include "scene/scene.h"
#include "support/executions.h"
#include "support/gpu_render.h"
#include "support/test_scenes.h"

namespace {

using namespace vkpath;

constexpr double Z_BOUND = 5.0;

// glTF's white metal (base colour 1, metallic 1) of roughness `roughness`:
// with compensation it reflects all the light at every angle.
scene::Material whiteMetal(float roughness) {
    scene::Material m;
    m.kind = scene::MaterialKind::MetallicRoughness;
    m.reflectance = glm::vec3(1.0f);
    m.metallic = 1.0f;
    m.roughness = roughness;
    return m;
}

// The square [-1, 1]^2 at z = 0 facing +z, its texture's u along +x (the
// tangent) and v down the square.
scene::Mesh texturedSquare() {
    scene::Mesh square;
    square.positions = {{-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}};
    square.texcoords0 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    square.triangles = {{0, 1, 2}, {0, 2, 3}};
    return square;
}

// A reference to a new texture of `s`: the image of `texels` (width x
// height, linear 16-bit), clamped at its edges.
scene::TextureRef addTexture(scene::Scene& s, uint32_t width, uint32_t height,
                             std::vector<glm::u16vec4> texels, bool nearest) {
    scene::TextureImage image;
    image.width = width;
    image.height = height;
    image.texels = std::move(texels);
    s.images.push_back(image);
    s.textures.push_back({uint32_t(s.images.size() - 1), scene::TextureWrap::ClampToEdge,
                          scene::TextureWrap::ClampToEdge, nearest});
    scene::TextureRef ref;
    ref.texture = int32_t(s.textures.size() - 1);
    return ref;
}

// Pixels of a 48 x 48 film whose footprint lies within 0.6 of its half-width
// of the centre: on the unit sphere seen from (0, 0, 4).
bool onTheSphere(uint32_t x, uint32_t y) {
    const double cx = (x + 0.5) / 48 * 2 - 1, cy = (y + 0.5) / 48 * 2 - 1;
    return cx * cx + cy * cy < 0.36;
}

// White furnace: a unit sphere of white metal under a white sheen, a smooth
// coat or both, in a sky of radiance 1. A white sheen takes
// max(sheenColor) E_sheen(mu_o) from a base that returns 1 and gives that
// back, and a smooth coat's mirror returns its share whole, so every pixel
// is 1: the sphere's mean is 1 within 5 standard errors + 2% (the base's
// compensation and the sheen's albedo each read from a table, each within 1%
// between grid points: tests/kernels/albedo_table_test.cpp). A sheen of
// colour 0.5 over a black base returns only the sheen, less than 0.5 (the
// power: a layer that reflected light without taking it from the base
// would not be caught otherwise).
TEST(LayerFurnace, WhiteLayersOverAWhiteBaseReturnAllTheLight) {
    struct Case {
        const char* name;
        float clearcoat;
        glm::vec3 sheen;
    };
    const Case cases[] = {
        {"white sheen", 0.0f, glm::vec3(1.0f)},
        {"smooth coat", 1.0f, glm::vec3(0.0f)},
        {"smooth coat over a white sheen", 1.0f, glm::vec3(1.0f)},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        scene::Scene s = test::sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(1.0f));
        s.materials[0] = whiteMetal(0.6f);
        s.materials[0].clearcoat = c.clearcoat;
        s.materials[0].sheenColor = c.sheen;
        s.materials[0].sheenRoughness = 0.5f;
        const auto r = test::renderGpu(s, test::squareSettings(48, 32, 5));
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        const auto sphere = image::regionMean(r.image, r.varianceOfMean, onTheSphere);
        ASSERT_GT(sphere.pixels, 100u);
        EXPECT_NEAR(sphere.mean, 1.0, Z_BOUND * sphere.standardError + 0.02);
        std::printf("  %s: %.4f +- %.4f\n", c.name, sphere.mean, sphere.standardError);
    }
    scene::Scene s = test::sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(1.0f));
    s.materials[0] = whiteMetal(0.6f);
    s.materials[0].reflectance = glm::vec3(0.0f);
    s.materials[0].sheenColor = glm::vec3(0.5f);
    s.materials[0].sheenRoughness = 0.5f;
    const auto r = test::renderGpu(s, test::squareSettings(48, 32, 5));
    const auto sphere = image::regionMean(r.image, r.varianceOfMean, onTheSphere);
    EXPECT_LT(sphere.mean, 0.5);
}

// A clear coat lies over the emission (KHR_materials_clearcoat) and dims it
// by what it reflects: a black sphere emitting 1 under a coat of weight 0.8
// in a black sky shows 1 - 0.8 F_c(n.v), F_c = 0.04 + 0.96 (1 - n.v)^5, with
// n.v from 1 at its centre to 0.53 at the edge of onTheSphere's disc (a
// ray 0.6 of the half-width off the axis, 40 degrees wide, passes 0.85 radii
// from the centre): the disc's mean lies between 1 - 0.8 F_c(0.52) and
// 1 - 0.8 F_c(1) = 0.968, and without the coat it is 1 exactly. (Found by BSDF samples alone, since
// the coated emitter is not light-sampled: the image is noise-free here.)
TEST(LayerRender, AClearCoatDimsTheEmissionUnderIt) {
    scene::Scene s = test::sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(1.0f));
    s.materials[0] = whiteMetal(0.5f);
    s.materials[0].reflectance = glm::vec3(0.0f);
    s.materials[0].metallic = 0.0f;
    s.materials[0].specular = 0.0f;
    s.materials[0].emission = glm::vec3(1.0f);
    s.environment->color = glm::vec3(0.0f);
    const auto bare = test::renderGpu(s, test::squareSettings(48, 4, 3));
    s.materials[0].clearcoat = 0.8f;
    const auto coated = test::renderGpu(s, test::squareSettings(48, 4, 3));
    const auto fc = [](double c) { return 0.04 + 0.96 * std::pow(1 - c, 5); };
    double sum = 0, bareSum = 0;
    size_t pixels = 0;
    for (uint32_t y = 0; y < 48; ++y)
        for (uint32_t x = 0; x < 48; ++x) {
            if (!onTheSphere(x, y)) continue;
            sum += coated.image.pixels[size_t(y) * 48 + x].x;
            bareSum += bare.image.pixels[size_t(y) * 48 + x].x;
            ++pixels;
        }
    EXPECT_DOUBLE_EQ(bareSum / double(pixels), 1.0);
    EXPECT_LT(sum / double(pixels), 1 - 0.8 * fc(1.0) + 1e-6);
    EXPECT_GT(sum / double(pixels), 1 - 0.8 * fc(0.52));
}

// A square (u along +x) of red plastic whose four layer textures are one
// 2 x 1 image sampled nearest: its left texel white and opaque, its right
// texel black and transparent. Where the texture is 1 the material is its
// factors' (a coat of 1, roughness 0.3; a pink sheen of roughness 0.5), where
// it is 0 it has no layer at all: the left half of the image holds the bits
// of the same square without textures, the right half those of the square
// without layers (the pixels whose samples all land on one side: away from
// the seam, two columns each side).
scene::Scene layeredSquare(bool textured, bool layered) {
    scene::Scene s;
    s.meshes.push_back(texturedSquare());
    scene::Material m;
    m.kind = scene::MaterialKind::MetallicRoughness;
    m.reflectance = {0.6f, 0.05f, 0.05f};
    m.roughness = 0.6f;
    if (layered) {
        m.clearcoat = 1.0f;
        m.clearcoatRoughness = 0.3f;
        m.sheenColor = {1.0f, 0.5f, 0.6f};
        m.sheenRoughness = 0.5f;
    }
    if (textured) {
        const scene::TextureRef ref =
            addTexture(s, 2, 1, {glm::u16vec4(65535), glm::u16vec4(0)}, true);
        m.clearcoatTexture = m.clearcoatRoughnessTexture = ref;
        m.sheenColorTexture = m.sheenRoughnessTexture = ref;
    }
    s.materials.push_back(m);
    scene::Environment sky;
    sky.color = glm::vec3(1.0f, 0.9f, 0.8f);
    s.environment = sky;
    s.camera.position = {0.3f, 0.4f, 2.5f};
    s.camera.target = {0, 0, 0};
    return s;
}

TEST(LayerTextures, ZeroTexelsRemoveTheLayers) {
    const auto settings = test::squareSettings(48, 8, 4);
    const auto textured = test::renderGpu(layeredSquare(true, true), settings);
    const auto factors = test::renderGpu(layeredSquare(false, true), settings);
    const auto bare = test::renderGpu(layeredSquare(false, false), settings);
    ASSERT_FALSE(test::sameBits(factors.image, bare.image)) << "the layers change nothing";
    // The seam, u = 0.5, is the square's x = 0: find the columns it crosses
    // from the render of the square alone (its left half lit as `factors`).
    size_t left = 0, right = 0;
    for (uint32_t y = 0; y < 48; ++y)
        for (uint32_t x = 0; x < 48; ++x) {
            const size_t i = size_t(y) * 48 + x;
            const glm::vec3 t = textured.image.pixels[i];
            const bool asFactors = t == factors.image.pixels[i];
            const bool asBare = t == bare.image.pixels[i];
            if (factors.image.pixels[i] == bare.image.pixels[i]) continue;  // the sky
            EXPECT_TRUE(asFactors || asBare) << "pixel " << x << ", " << y;
            left += asFactors && x < 20;
            right += asBare && x > 28;
            EXPECT_FALSE(asFactors && x > 28) << "a layer right of the seam at " << x << ", " << y;
            EXPECT_FALSE(asBare && x < 20) << "no layer left of the seam at " << x << ", " << y;
        }
    EXPECT_GT(left, 200u);
    EXPECT_GT(right, 200u);
}

// Wavefront, megakernel and general kernel the same bits, the CPU reference
// the same image (block z-test), on the textured square with a layered
// sphere and a rough thin-walled sphere beside it.
TEST(LayerRender, EveryExecutionAgrees) {
    scene::Scene s = layeredSquare(true, true);
    scene::Material sphere = whiteMetal(0.4f);
    sphere.reflectance = {0.9f, 0.6f, 0.3f};
    sphere.metallic = 0.3f;
    sphere.clearcoat = 0.7f;
    sphere.clearcoatRoughness = 0.05f;
    sphere.sheenColor = {0.3f, 0.6f, 1.0f};
    sphere.sheenRoughness = 0.3f;
    s.materials.push_back(sphere);
    s.spheres.push_back({"ball", {0.6f, 0.0f, 0.5f}, 0.4f, 1});
    scene::Material bubble;
    bubble.kind = scene::MaterialKind::RoughDielectric;
    bubble.roughness = 0.3f;
    bubble.reflectance = glm::vec3(1.0f);
    bubble.transmittance = {0.8f, 0.9f, 1.0f};
    bubble.thinWalled = true;
    s.materials.push_back(bubble);
    s.spheres.push_back({"bubble", {-0.5f, 0.2f, 0.6f}, 0.35f, 2});
    test::expectEveryExecutionAgrees(s, test::squareSettings(24, 8, 4));
}

// A square whose diffuse lobe passes all its light to the back, tinted c
// (base colour black, no specular layer: KHR_materials_diffuse_transmission
// 1), in a sky of radiance 1: it shows the sky behind it, diffused, so every
// pixel well inside the square is c (the cosine-weighted integral of the
// sky behind, over pi), within 5 standard errors. From the back it looks the
// same.
TEST(DiffuseTransmissionRender, ASquareShowsTheSkyBehindIt) {
    const glm::vec3 tint(0.8f, 0.5f, 0.2f);
    for (float side : {1.0f, -1.0f}) {
        SCOPED_TRACE(side > 0 ? "front" : "back");
        scene::Scene s;
        scene::Mesh square;
        square.positions = {{-2, 2, 0}, {-2, -2, 0}, {2, -2, 0}, {2, 2, 0}};
        square.triangles = {{0, 1, 2}, {0, 2, 3}};
        s.meshes.push_back(square);
        scene::Material leaf;
        leaf.kind = scene::MaterialKind::MetallicRoughness;
        leaf.reflectance = glm::vec3(0.0f);
        leaf.specular = 0.0f;
        leaf.roughness = 0.5f;
        leaf.diffuseTransmission = 1.0f;
        leaf.diffuseTransmissionColor = tint;
        s.materials.push_back(leaf);
        scene::Environment sky;
        sky.color = glm::vec3(1.0f);
        s.environment = sky;
        s.camera.position = {0, 0, 3 * side};
        s.camera.target = {0, 0, 0};
        s.camera.xfovDegrees = 30.0f;
        const auto r = test::renderGpu(s, test::squareSettings(32, 32, 4));
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        for (int c = 0; c < 3; ++c) {
            double sum = 0, variance = 0;
            size_t n = 0;
            for (uint32_t y = 8; y < 24; ++y)
                for (uint32_t x = 8; x < 24; ++x) {
                    sum += r.image.pixels[y * 32 + x][c];
                    variance += r.varianceOfMean.pixels[y * 32 + x][c];
                    ++n;
                }
            const double mean = sum / n, standardError = std::sqrt(variance) / n;
            EXPECT_NEAR(mean, tint[c], Z_BOUND * standardError + 1e-6) << "channel " << c;
        }
    }
}

// A square of smooth thin-walled glass (index 1.5, tint 0.5) facing the
// camera in a sky of radiance 1: a pixel sees the sky reflected with
// probability F and through the wall, tinted, otherwise; near the image's
// centre (cos theta_o > 0.99, where F stays within 1e-5 of its normal value
// 0.04) the mean is F + (1 - F) 0.5 = 0.52 within 5 standard errors + 1e-4.
// A solid of the same glass would refract the rays into its inside and leave
// them there (the square has no back face to leave by): far less.
TEST(ThinWallRender, SmoothPaneShowsTheSkyThroughIt) {
    scene::Scene s;
    scene::Mesh pane;
    pane.positions = {{-2, 2, 0}, {-2, -2, 0}, {2, -2, 0}, {2, 2, 0}};
    pane.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.meshes.push_back(pane);
    scene::Material glass;
    glass.kind = scene::MaterialKind::Dielectric;
    glass.reflectance = glm::vec3(1.0f);
    glass.transmittance = glm::vec3(0.5f);
    glass.thinWalled = true;
    s.materials.push_back(glass);
    scene::Environment sky;
    sky.color = glm::vec3(1.0f);
    s.environment = sky;
    s.camera.position = {0, 0, 3};
    s.camera.target = {0, 0, 0};
    s.camera.xfovDegrees = 30.0f;
    const auto r = test::renderGpu(s, test::squareSettings(32, 256, 4));
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    const auto centre = image::regionMean(r.image, r.varianceOfMean, [](uint32_t x, uint32_t y) {
        const double cx = (x + 0.5) / 32 * 2 - 1, cy = (y + 0.5) / 32 * 2 - 1;
        return cx * cx + cy * cy < 0.25;  // within 8 degrees of the axis
    });
    EXPECT_NEAR(centre.mean, 0.52, Z_BOUND * centre.standardError + 1e-4);
    std::printf("  centre %.5f +- %.5f\n", centre.mean, centre.standardError);
}

// The fog lies on both sides of a thin wall: the camera inside a lamp
// sphere of radius 2 in an absorbing fog sees the lamp through a thin wall
// of index 1 (it neither reflects nor bends) whose back faces the camera,
// exactly as without the wall, exp(-2 sigma) (to 1e-5: float rounding). Were
// the wall a solid's surface, the segment that reaches it from behind would
// lie in its clear inside.
TEST(ThinWallRender, KeepsTheFogBehindIt) {
    scene::Scene s = test::cameraInsideALampSphere(2.0f);
    s.fog.absorption = {0.1f, 0.5f, 1.5f};
    scene::Mesh wall;  // at z = -0.5, wound so that its normal is -z, away from the camera
    wall.positions = {
        {-1.9f, 1.9f, -0.5f}, {1.9f, 1.9f, -0.5f}, {1.9f, -1.9f, -0.5f}, {-1.9f, -1.9f, -0.5f}};
    wall.triangles = {{0, 1, 2}, {0, 2, 3}};
    wall.material = 1;
    s.meshes.push_back(wall);
    scene::Material thin;
    thin.kind = scene::MaterialKind::Dielectric;
    thin.ior = 1.0f;
    thin.reflectance = thin.transmittance = glm::vec3(1.0f);
    thin.thinWalled = true;
    s.materials.push_back(thin);
    const auto r = test::renderGpu(s, test::squareSettings(16, 4, 3));
    for (const glm::vec3& p : r.image.pixels)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(p[c], std::exp(-2.0 * s.fog.absorption[c]),
                        1e-5 * std::exp(-2.0 * s.fog.absorption[c]))
                << c;
}

// A square of brushed white metal (roughness 0.1, anisotropy 0.9: alpha 0.82
// along the direction, 0.01 across) facing the camera, its texture's u along
// +x (the tangent), lit by a small lamp behind the camera in a black sky:
// the lamp's highlight is a streak along the direction. `rotation` turns the
// direction; `texel`, where given, is the anisotropy texture's one texel
// (RG the direction in the tangent frame, B the strength's factor).
scene::Scene brushedSquare(float rotation, std::optional<glm::u16vec4> texel = std::nullopt) {
    scene::Scene s;
    s.meshes.push_back(texturedSquare());
    scene::Material m;
    m.kind = scene::MaterialKind::Conductor;
    m.reflectance = glm::vec3(0.9f);
    m.roughness = 0.1f;
    m.anisotropy = 0.9f;
    m.anisotropyRotation = rotation;
    if (texel) m.anisotropyTexture = addTexture(s, 1, 1, {*texel}, false);
    s.materials.push_back(m);
    scene::Material lamp;
    lamp.emission = glm::vec3(400.0f);
    s.materials.push_back(lamp);
    s.spheres.push_back({"lamp", {0.0f, 0.5f, 3.5f}, 0.05f, 1});
    s.camera.position = {0.0f, 0.0f, 3.0f};
    s.camera.target = {0, 0, 0};
    return s;
}

// The luminance-weighted spread of `image` (width `size`) along x and y
// about its centroid.
glm::dvec2 spread(const image::Image& image, uint32_t size) {
    double sum = 0;
    glm::dvec2 mean(0), square(0);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const glm::vec3 p = image.pixels[size_t(y) * size + x];
            const double w = p.x + p.y + p.z;
            sum += w;
            mean += w * glm::dvec2(x, y);
            square += w * glm::dvec2(double(x) * x, double(y) * y);
        }
    mean /= sum;
    return glm::sqrt(square / sum - mean * mean);
}

// The streak lies along the direction: along x (the tangent) unturned, along
// y turned by 90 degrees, at least twice as long as it is wide (an isotropic
// lobe's highlight is round). The texture's direction (0, 1) at strength
// factor 1 renders as the rotation of 90 degrees: the two images differ by
// less than 1% of what separates them from the unturned one (the texel's
// 16-bit rounding turns the direction by 1.5e-5 rad).
TEST(AnisotropyRender, TheHighlightStretchesAlongTheDirection) {
    const uint32_t size = 48;
    const auto settings = test::squareSettings(size, 16, 2);
    const auto along = test::renderGpu(brushedSquare(0.0f), settings);
    const auto turned = test::renderGpu(brushedSquare(1.5707964f), settings);
    const auto textured =
        test::renderGpu(brushedSquare(0.0f, glm::u16vec4(32768, 65535, 65535, 65535)), settings);
    const glm::dvec2 a = spread(along.image, size), t = spread(turned.image, size);
    EXPECT_GT(a.x, 2 * a.y) << "spread " << a.x << " x " << a.y;
    EXPECT_GT(t.y, 2 * t.x) << "spread " << t.x << " x " << t.y;
    const double apart = image::compareImages(along.image, turned.image).overall.relMse;
    EXPECT_LT(image::compareImages(textured.image, turned.image).overall.relMse, 0.01 * apart);
}

// Wavefront, megakernel and general kernel the same bits, the CPU reference
// the same image (block z-test), on the brushed square with its texture.
TEST(AnisotropyRender, EveryExecutionAgrees) {
    test::expectEveryExecutionAgrees(brushedSquare(0.4f, glm::u16vec4(60000, 20000, 50000, 65535)),
                                     test::squareSettings(24, 8, 3));
}

// A black square under a clear coat of roughness 0.05 whose own normal map
// (one texel) tilts the coat's normal `tilt` radians toward +x (the
// tangent), lit by the small lamp above the camera in a black sky: only the
// coat reflects, and the lamp's reflection lies where the tilted normal
// bisects the directions to the lamp and the camera.
scene::Scene coatedSquare(float tilt) {
    scene::Scene s = brushedSquare(0.0f);
    scene::Material& m = s.materials[0];
    m = scene::Material{};
    m.kind = scene::MaterialKind::MetallicRoughness;
    m.reflectance = glm::vec3(0.0f);
    m.specular = 0.0f;
    m.roughness = 0.5f;
    m.clearcoat = 1.0f;
    m.clearcoatRoughness = 0.05f;
    if (tilt != 0.0f) {
        const auto encode = [](float c) { return uint16_t(std::lround((c + 1) / 2 * 65535)); };
        m.clearcoatNormalTexture = addTexture(
            s, 1, 1,
            {glm::u16vec4(encode(std::sin(tilt)), encode(0.0f), encode(std::cos(tilt)), 65535)},
            false);
    }
    return s;
}

// Tilted 0.1 rad toward +x, the reflection moves toward -x by about 3 x 0.1
// m at the camera's 3 m (image left, 6 pixels of 48 at this field of view):
// its centroid at least 3 pixels left of the untilted one's.
TEST(LayerRender, ACoatNormalMapTurnsTheCoatsReflection) {
    const uint32_t size = 48;
    const auto settings = test::squareSettings(size, 16, 2);
    const auto flat = test::renderGpu(coatedSquare(0.0f), settings);
    const auto turned = test::renderGpu(coatedSquare(0.1f), settings);
    const auto centroidX = [&](const image::Image& image) {
        double sum = 0, x = 0;
        for (uint32_t j = 0; j < size; ++j)
            for (uint32_t i = 0; i < size; ++i) {
                const glm::vec3 p = image.pixels[size_t(j) * size + i];
                sum += p.x + p.y + p.z;
                x += (p.x + p.y + p.z) * i;
            }
        return x / sum;
    };
    EXPECT_LT(centroidX(turned.image), centroidX(flat.image) - 3.0)
        << centroidX(turned.image) << " against " << centroidX(flat.image);
}

// Wavefront, megakernel and general kernel the same bits, the CPU reference
// the same image (block z-test), on the coat with its own normal map.
TEST(LayerRender, EveryExecutionAgreesOnACoatNormalMap) {
    test::expectEveryExecutionAgrees(coatedSquare(0.2f), test::squareSettings(24, 8, 3));
}

}  // namespace
