// glTF normalTexture as the importer reads it (scene/gltf_materials.cpp):
// the texture with its sampler and decoded texels, texCoord, scale and
// KHR_texture_transform into scene::Material::normalTexture and normalScale,
// a warning where the transform turns the map (the tangent frame does not
// follow it), and bad references and numbers as one-line errors naming the
// file.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "image/image.h"
#include "support/gltf_builder.h"
#include "support/temp_dir.h"
#include "wavefront/texture_tables.h"

namespace {

using namespace vkpath;
using test::GltfBuilder;
using test::Json;
using test::load;
using test::Loaded;
using test::loadError;
using test::TempDir;

// A PNG of 8-bit RGB texels, row by row, written by the project's own PNG
// writer from linear values whose sRGB encoding rounds back to the bytes.
void writeTexelsPng(const std::filesystem::path& path, uint32_t width, uint32_t height,
                    const std::vector<glm::ivec3>& texels) {
    image::Image image;
    image.width = width;
    image.height = height;
    for (const glm::ivec3& t : texels)
        image.pixels.emplace_back(wavefront::srgbToLinear(t.x / 255.0),
                                  wavefront::srgbToLinear(t.y / 255.0),
                                  wavefront::srgbToLinear(t.z / 255.0));
    image::writePng(path, image);
}

// A file with one triangle whose material has `normalTexture` (and is
// otherwise a plain diffuse one, so nothing else warns), the texture being
// a 2 x 1 PNG read with nearest filtering and clamped in u.
std::filesystem::path writeNormalMapped(const TempDir& dir, const Json& normalTexture) {
    writeTexelsPng(dir / "normal.png", 2, 1, {{200, 100, 240}, {60, 128, 255}});
    GltfBuilder g;
    g.doc["extensionsUsed"] = {"KHR_texture_transform"};
    g.doc["samplers"] = {{{"magFilter", 9728}, {"wrapS", 33071}}};
    g.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    g.doc["images"] = {{{"uri", "normal.png"}}};
    const int material = g.material({{"name", "bumpy"},
                                     {"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                                     {"normalTexture", normalTexture}});
    g.node({{"mesh", g.triangle(material)}});
    g.camera();
    return g.writeGltf(dir / "normal.gltf");
}

TEST(GltfNormalMaps, TextureScaleAndTransformAreRead) {
    TempDir dir;
    const Loaded loaded = load(writeNormalMapped(
        dir, {{"index", 0},
              {"scale", 0.5},
              {"extensions",
               {{"KHR_texture_transform", {{"offset", {0.25, 0.5}}, {"scale", {2, 2}}}}}}}));
    EXPECT_EQ(loaded.warnings, "") << "the map is applied: no warning";
    const scene::Material& m = loaded.scene.materials.at(0);
    ASSERT_TRUE(m.normalTexture.present());
    EXPECT_FALSE(m.baseColorTexture.present());
    EXPECT_EQ(m.normalScale, 0.5f);
    EXPECT_EQ(m.normalTexture.texCoord, 0u);
    EXPECT_EQ(m.normalTexture.offset, glm::vec2(0.25f, 0.5f));
    EXPECT_EQ(m.normalTexture.scale, glm::vec2(2.0f));
    const scene::Texture& t = loaded.scene.textures.at(size_t(m.normalTexture.texture));
    EXPECT_TRUE(t.nearest);
    EXPECT_EQ(t.wrapU, scene::TextureWrap::ClampToEdge);
    EXPECT_EQ(t.wrapV, scene::TextureWrap::Repeat);
    const scene::TextureImage& image = loaded.scene.images.at(t.image);
    ASSERT_EQ(image.width, 2u);
    ASSERT_EQ(image.height, 1u);
    EXPECT_EQ(image.texels[0], glm::u16vec4(200 * 257, 100 * 257, 240 * 257, 65535));
    EXPECT_EQ(image.texels[1], glm::u16vec4(60 * 257, 128 * 257, 255 * 257, 65535));

    // Without a scale, 1 (glTF 2.0, 5.23).
    EXPECT_EQ(load(writeNormalMapped(dir, {{"index", 0}})).scene.materials.at(0).normalScale, 1.0f);
}

// The tangent frame follows the texture coordinates, not the transform: a
// map turned (or scaled unevenly) by KHR_texture_transform is read, and said
// once to be approximated. The extension's texCoord overrides the map's.
TEST(GltfNormalMaps, TurnedMapIsReadWithAWarning) {
    TempDir dir;
    const Loaded loaded = load(writeNormalMapped(
        dir, {{"index", 0},
              {"extensions", {{"KHR_texture_transform", {{"rotation", 0.3}, {"texCoord", 1}}}}}}));
    const scene::Material& m = loaded.scene.materials.at(0);
    ASSERT_TRUE(m.normalTexture.present());
    EXPECT_EQ(m.normalTexture.texCoord, 1u);
    EXPECT_FLOAT_EQ(m.normalTexture.rotation, 0.3f);
    EXPECT_EQ(std::count(loaded.warnings.begin(), loaded.warnings.end(), '\n'), 1)
        << loaded.warnings;
    EXPECT_NE(loaded.warnings.find("normal maps turned or unevenly scaled"), std::string::npos)
        << loaded.warnings;

    const Loaded uneven = load(writeNormalMapped(
        dir, {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {1, -1}}}}}}}));
    EXPECT_NE(uneven.warnings.find("normal maps turned or unevenly scaled"), std::string::npos)
        << uneven.warnings;
}

// A map read from TEXCOORD_2 (vkpath keeps two sets) is left out with the
// importer's warning; a texture index out of range and a scale that is not
// a finite number are errors naming the file and the material.
TEST(GltfNormalMaps, UnusableReferences) {
    TempDir dir;
    const Loaded third = load(writeNormalMapped(dir, {{"index", 0}, {"texCoord", 2}}));
    EXPECT_FALSE(third.scene.materials.at(0).normalTexture.present());
    EXPECT_NE(third.warnings.find("TEXCOORD_2"), std::string::npos) << third.warnings;

    const std::string outOfRange = loadError(writeNormalMapped(dir, {{"index", 3}}));
    EXPECT_NE(outOfRange.find("normalTexture"), std::string::npos) << outOfRange;
    EXPECT_NE(outOfRange.find("bumpy"), std::string::npos) << outOfRange;

    // JSON has no infinity, and a number beyond a double (1e999) is refused
    // by the parser already: one line naming the file (the importer's own
    // check of the scale stays, for a parser that rounds it to infinity).
    const std::filesystem::path path = writeNormalMapped(dir, {{"index", 0}, {"scale", 12345.5}});
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("12345.5"), 7, "1e999");
    test::writeText(path, text);
    const std::string infinite = loadError(path);
    EXPECT_NE(infinite.find("1e999"), std::string::npos) << infinite;
}

}  // namespace
