// The glTF importer's textures (host/scene/gltf_textures): images decoded with
// OpenImageIO from a file, a data URI and a bufferView, samplers,
// KHR_texture_transform, texture coordinate sets, and what is refused or
// warned about.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/gltf_builder.h"
#include "support/temp_dir.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;
using test::GltfBuilder;
using test::Json;
using test::load;
using test::loadError;
using test::TempDir;

// A 3 x 2 RGBA PNG: texel (i, j) = (40 i, 100 j, 7, 255 - 50 i), 8-bit. The
// translucent texels check that decoding keeps straight alpha (OpenImageIO
// premultiplies by default, which rounds their colours).
std::vector<uint8_t> pngBytes(const fs::path& scratch) {
    std::vector<uint8_t> pixels;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i)
            pixels.insert(pixels.end(),
                          {uint8_t(40 * i), uint8_t(100 * j), 7, uint8_t(255 - 50 * i)});
    auto out = OIIO::ImageOutput::create(scratch.string());
    // Straight alpha, as PNG stores it (else OpenImageIO divides the colours by alpha).
    OIIO::ImageSpec spec(3, 2, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    EXPECT_TRUE(out && out->open(scratch.string(), spec) &&
                out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
    std::ifstream in(scratch, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expectDecoded(const scene::TextureImage& image) {
    ASSERT_EQ(image.width, 3u);
    ASSERT_EQ(image.height, 2u);
    for (uint32_t j = 0; j < 2; ++j)
        for (uint32_t i = 0; i < 3; ++i)
            EXPECT_EQ(image.texels[j * 3 + i],
                      glm::u16vec4(40 * i * 257, 100 * j * 257, 7 * 257, (255 - 50 * i) * 257));
}

// One textured triangle whose material's baseColorTexture is texture 0 of `image`.
GltfBuilder texturedTriangle(const Json& image, const Json& textureInfo = {{"index", 0}}) {
    GltfBuilder g;
    g.doc["images"] = {image};
    g.doc["textures"] = {{{"source", 0}}};
    const int m = g.material(
        {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"baseColorTexture", textureInfo}}}});
    g.node({{"mesh", g.triangle(m)}});
    g.camera();
    return g;
}

TEST(GltfTextures, ImagesAreDecodedFromAFileADataUriAndABufferView) {
    TempDir dir;
    const std::vector<uint8_t> png = pngBytes(dir / "t.png");
    {
        const auto loaded = load(texturedTriangle({{"uri", "t.png"}}).writeGltf(dir / "file.gltf"));
        ASSERT_EQ(loaded.scene.images.size(), 1u) << loaded.warnings;
        expectDecoded(loaded.scene.images[0]);
        EXPECT_EQ(loaded.scene.materials[0].baseColorTexture.texture, 0);
        EXPECT_TRUE(std::any_of(loaded.scene.referencedFiles.begin(),
                                loaded.scene.referencedFiles.end(),
                                [](const fs::path& p) { return p.filename() == "t.png"; }))
            << "the image is part of the render's identity";
    }
    {
        const auto loaded =
            load(texturedTriangle({{"uri", "data:image/png;base64," + test::base64(png)}})
                     .writeGltf(dir / "data.gltf"));
        ASSERT_EQ(loaded.scene.images.size(), 1u) << loaded.warnings;
        expectDecoded(loaded.scene.images[0]);
    }
    {
        GltfBuilder g = texturedTriangle({{"mimeType", "image/png"}});
        g.doc["images"][0]["bufferView"] = g.view(png.data(), png.size());
        const auto loaded = load(g.writeGlb(dir / "view.glb"));
        ASSERT_EQ(loaded.scene.images.size(), 1u) << loaded.warnings;
        expectDecoded(loaded.scene.images[0]);
    }
}

TEST(GltfTextures, SamplersTransformsAndTexCoords) {
    TempDir dir;
    pngBytes(dir / "t.png");
    GltfBuilder g = texturedTriangle(
        {{"uri", "t.png"}},
        {{"index", 0},
         {"texCoord", 0},
         {"extensions",
          {{"KHR_texture_transform",
            {{"offset", {0.5, -0.25}}, {"rotation", 0.75}, {"scale", {2, 3}}, {"texCoord", 1}}}}}});
    g.doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}}};
    g.doc["textures"][0]["sampler"] = 0;
    g.doc["extensionsUsed"] = {"KHR_texture_transform"};
    const auto loaded = load(g.writeGltf(dir / "s.gltf"));
    EXPECT_EQ(loaded.warnings, "");
    ASSERT_EQ(loaded.scene.textures.size(), 1u);
    const scene::Texture& t = loaded.scene.textures[0];
    EXPECT_EQ(t.wrapU, scene::TextureWrap::ClampToEdge);
    EXPECT_EQ(t.wrapV, scene::TextureWrap::MirroredRepeat);
    EXPECT_TRUE(t.nearest);
    const scene::TextureRef& ref = loaded.scene.materials[0].baseColorTexture;
    EXPECT_EQ(ref.texCoord, 1u) << "the extension's texCoord overrides the textureInfo's";
    EXPECT_EQ(ref.offset, glm::vec2(0.5f, -0.25f));
    EXPECT_FLOAT_EQ(ref.rotation, 0.75f);
    EXPECT_EQ(ref.scale, glm::vec2(2.0f, 3.0f));

    // The defaults: REPEAT both ways, bilinear.
    const auto plain = load(texturedTriangle({{"uri", "t.png"}}).writeGltf(dir / "plain.gltf"));
    ASSERT_EQ(plain.scene.textures.size(), 1u);
    EXPECT_EQ(plain.scene.textures[0].wrapU, scene::TextureWrap::Repeat);
    EXPECT_EQ(plain.scene.textures[0].wrapV, scene::TextureWrap::Repeat);
    EXPECT_FALSE(plain.scene.textures[0].nearest);
}

TEST(GltfTextures, WhatCannotBeUsedIsWarnedAboutOnce) {
    TempDir dir;
    pngBytes(dir / "t.png");
    // A third texture coordinate set: warned, the texture left out.
    const auto set2 = load(texturedTriangle({{"uri", "t.png"}}, {{"index", 0}, {"texCoord", 2}})
                               .writeGltf(dir / "c.gltf"));
    EXPECT_FALSE(set2.scene.materials[0].baseColorTexture.present());
    EXPECT_NE(set2.warnings.find("TEXCOORD_2"), std::string::npos) << set2.warnings;
    // An image OpenImageIO cannot read (KTX2 is not among its formats): warned, left out.
    test::writeText(dir / "t.ktx2",
                    std::string("\xABKTX 20\xBB\r\n\x1A\n", 12) + std::string(64, '\0'));
    const auto ktx = load(texturedTriangle({{"uri", "t.ktx2"}}).writeGltf(dir / "k.gltf"));
    EXPECT_TRUE(ktx.scene.images.empty());
    EXPECT_FALSE(ktx.scene.materials[0].baseColorTexture.present());
    EXPECT_NE(ktx.warnings.find("images that cannot be decoded (ktx2)"), std::string::npos)
        << ktx.warnings;
}

TEST(GltfTextures, BadIndicesAndTransformsAreOneLineErrors) {
    TempDir dir;
    pngBytes(dir / "t.png");
    {
        GltfBuilder g = texturedTriangle({{"uri", "t.png"}}, {{"index", 3}});
        EXPECT_NE(loadError(g.writeGltf(dir / "a.gltf")).find("texture 3"), std::string::npos);
    }
    {
        GltfBuilder g = texturedTriangle({{"uri", "t.png"}});
        g.doc["textures"][0]["sampler"] = 2;
        EXPECT_NE(loadError(g.writeGltf(dir / "b.gltf")).find("sampler 2"), std::string::npos);
    }
    {
        GltfBuilder g = texturedTriangle(
            {{"uri", "t.png"}},
            {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {1}}}}}}});
        EXPECT_NE(loadError(g.writeGltf(dir / "c.gltf")).find("KHR_texture_transform.scale"),
                  std::string::npos);
    }
}

}  // namespace
