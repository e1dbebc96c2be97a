// COLLADA diffuse textures (scene/collada_textures): <diffuse><texture>
// resolved through the effect's sampler2D and surface newparams (and the
// shorter forms exporters write) to an <image> file inside the scene's
// folder, held to the glTF importer's URI rule; decoding failures are a
// warning, bad references one error line. Then Assimp's duck (Debian's
// assimp-testmodels, read where the package puts it): its texture is the TGA's
// texels, a quad wearing that texture under a white sky shows the texels'
// sRGB-decoded mean within noise, and duck.dae renders in its colours.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "input_error.h"
#include "scene/camera.h"
#include "scene/collada_loader.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/textured_render.h"

namespace {

using namespace vkpath;
namespace fs = std::filesystem;
using test::TempDir;

const fs::path DUCK_FOLDER = "/usr/share/assimp/models/Collada";

// The newparams of duck.dae's shape: sampler2D "tex-sampler" whose source is
// surface "tex-surface", initialised from the image id `image`.
std::string samplerAndSurface(const std::string& image, const std::string& samplerStates = "") {
    return R"(<newparam sid="tex-surface"><surface type="2D"><init_from>)" + image +
           R"(</init_from></surface></newparam>
           <newparam sid="tex-sampler"><sampler2D><source>tex-surface</source>)" +
           samplerStates + "</sampler2D></newparam>";
}

// A unit square in z = 0 facing +z, texture coordinates (s, t) = (x, y) +
// 0.5 (so the image stands upright seen from +z), its material's effect
// built from `newparams` and `diffuse`, and a camera looking along -z.
struct Doc {
    std::string images = R"(<image id="tex" name="tex"><init_from>tex.png</init_from></image>)";
    std::string newparams = samplerAndSurface("tex");
    std::string diffuse = R"(<texture texture="tex-sampler" texcoord="UV0"/>)";
    bool texcoords = true;
    std::string extraMaterials;  // more <material>s and their effects' XML, with extraEffects
    std::string extraEffects;
};

std::string xml(const Doc& d) {
    std::string s = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Y_UP</up_axis></asset>
  <library_cameras><camera id="cam" name="cam"><optics><technique_common><perspective>
    <xfov>50</xfov><aspect_ratio>1.3333333</aspect_ratio>
  </perspective></technique_common></optics></camera></library_cameras>
  <library_images>)" +
                    d.images + R"(</library_images>
  <library_effects><effect id="textured-effect"><profile_COMMON>)" +
                    d.newparams + R"(<technique sid="common"><lambert><diffuse>)" + d.diffuse +
                    R"(</diffuse></lambert></technique></profile_COMMON></effect>)" +
                    d.extraEffects +
                    R"(</library_effects>
  <library_materials><material id="textured" name="textured"><instance_effect url="#textured-effect"/></material>)" +
                    d.extraMaterials + R"(</library_materials>
  <library_geometries><geometry id="square" name="square"><mesh>
    <source id="positions"><float_array id="positions-array" count="12">
      -0.5 -0.5 0  0.5 -0.5 0  0.5 0.5 0  -0.5 0.5 0</float_array>
      <technique_common><accessor source="#positions-array" count="4" stride="3"/></technique_common></source>
    <source id="uvs"><float_array id="uvs-array" count="8">0 0  1 0  1 1  0 1</float_array>
      <technique_common><accessor source="#uvs-array" count="4" stride="2"/></technique_common></source>
    <vertices id="vertices"><input semantic="POSITION" source="#positions"/></vertices>
    <polylist material="textured" count="2">
      <input semantic="VERTEX" source="#vertices" offset="0"/>)";
    s += d.texcoords ? R"(<input semantic="TEXCOORD" source="#uvs" offset="1" set="0"/>
      <vcount>3 3</vcount><p>0 0 1 1 2 2  0 0 2 2 3 3</p>)"
                     : "<vcount>3 3</vcount><p>0 1 2  0 2 3</p>";
    s += R"(</polylist>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="Scene" name="Scene">
    <node id="Camera" name="Camera"><matrix>1 0 0 0  0 1 0 0  0 0 1 3  0 0 0 1</matrix>
      <instance_camera url="#cam"/></node>
    <node id="Square" name="Square"><instance_geometry url="#square"><bind_material><technique_common>
      <instance_material symbol="textured" target="#textured">
        <bind_vertex_input semantic="UV0" input_semantic="TEXCOORD" input_set="0"/>
      </instance_material></technique_common></bind_material></instance_geometry></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
    return s;
}

// A 2 x 2 8-bit RGB PNG: texel i has red 60 i + 10, green 200 - 50 i, blue 30.
void writeTestPng(const fs::path& path) {
    const std::vector<uint8_t> rgb = {10, 200, 30, 70, 150, 30, 130, 100, 30, 190, 50, 30};
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    const OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::UINT8);
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()));
    out->close();
}

scene::Scene load(const fs::path& path, std::vector<std::string>* warnings = nullptr) {
    std::vector<std::string> sink;
    return scene::loadCollada(path, {}, warnings ? warnings : &sink);
}

std::string loadError(const fs::path& path) {
    try {
        load(path);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << path << " loaded without an error";
    return {};
}

bool anyContains(const std::vector<std::string>& lines, const std::string& text) {
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

const scene::Material& squareMaterial(const scene::Scene& s) {
    return s.materials.at(s.meshes.at(0).material);
}

TEST(ColladaTextures, DiffuseTextureIsResolvedThroughSamplerAndSurface) {
    TempDir dir;
    writeTestPng(dir / "tex.png");
    std::vector<std::string> warnings;
    const scene::Scene s = load(dir.write("square.dae", xml(Doc())), &warnings);
    EXPECT_FALSE(anyContains(warnings, "textur")) << warnings.size();
    const scene::Material& m = squareMaterial(s);
    EXPECT_EQ(m.kind, scene::MaterialKind::Diffuse);
    EXPECT_EQ(m.reflectance, glm::vec3(1.0f)) << "the texture is the albedo";
    ASSERT_EQ(m.baseColorTexture.texture, 0);
    EXPECT_EQ(m.baseColorTexture.texCoord, 0u);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.textures[0].image, 0u);
    EXPECT_EQ(s.textures[0].wrapU, scene::TextureWrap::Repeat) << "COLLADA's default wrap";
    EXPECT_EQ(s.textures[0].wrapV, scene::TextureWrap::Repeat);
    EXPECT_FALSE(s.textures[0].nearest);
    ASSERT_EQ(s.images.size(), 1u);
    ASSERT_EQ(s.images[0].width, 2u);
    ASSERT_EQ(s.images[0].height, 2u);
    EXPECT_EQ(s.images[0].name, "tex");
    for (int i = 0; i < 4; ++i)
        EXPECT_EQ(s.images[0].texels[size_t(i)],
                  glm::u16vec4((60 * i + 10) * 257, (200 - 50 * i) * 257, 30 * 257, 65535))
            << "texel " << i;
    EXPECT_NE(std::find(s.referencedFiles.begin(), s.referencedFiles.end(), dir / "tex.png"),
              s.referencedFiles.end())
        << "the image is part of the render's identity";
    EXPECT_EQ(s.meshes.at(0).texcoords0.size(), s.meshes.at(0).positions.size());
}

TEST(ColladaTextures, SamplerStatesAndTheShorterForms) {
    TempDir dir;
    writeTestPng(dir / "tex.png");

    Doc states;
    states.newparams = samplerAndSurface(
        "tex", "<wrap_s>MIRROR</wrap_s><wrap_t>CLAMP</wrap_t><magfilter>NEAREST</magfilter>");
    const scene::Scene a = load(dir.write("states.dae", xml(states)));
    ASSERT_EQ(a.textures.size(), 1u);
    EXPECT_EQ(a.textures[0].wrapU, scene::TextureWrap::MirroredRepeat);
    EXPECT_EQ(a.textures[0].wrapV, scene::TextureWrap::ClampToEdge);
    EXPECT_TRUE(a.textures[0].nearest);

    Doc border;
    border.newparams = samplerAndSurface("tex", "<wrap_s>BORDER</wrap_s>");
    std::vector<std::string> warnings;
    const scene::Scene b = load(dir.write("border.dae", xml(border)), &warnings);
    EXPECT_EQ(b.textures.at(0).wrapU, scene::TextureWrap::ClampToEdge);
    EXPECT_TRUE(anyContains(warnings, "BORDER, NONE and MIRROR_ONCE are read as CLAMP"))
        << warnings.size();

    // The image named in texture="..." directly, without newparams.
    Doc direct;
    direct.newparams = "";
    direct.diffuse = R"(<texture texture="tex" texcoord="UV0"/>)";
    EXPECT_EQ(squareMaterial(load(dir.write("direct.dae", xml(direct)))).baseColorTexture.texture,
              0);

    // COLLADA 1.5: <instance_image> in the sampler, <init_from><ref> in the image.
    Doc v15;
    v15.images = R"(<image id="tex" name="tex"><init_from><ref>tex.png</ref></init_from></image>)";
    v15.newparams =
        R"(<newparam sid="tex-sampler"><sampler2D><instance_image url="#tex"/></sampler2D></newparam>)";
    EXPECT_EQ(squareMaterial(load(dir.write("v15.dae", xml(v15)))).baseColorTexture.texture, 0);
}

TEST(ColladaTextures, AnImageUsedTwiceIsReadOnce) {
    TempDir dir;
    writeTestPng(dir / "tex.png");
    Doc d;
    // A second material with its own newparams naming a second <image> of the same file.
    d.images += R"(<image id="again" name="again"><init_from>./tex.png</init_from></image>)";
    d.extraEffects =
        R"(<effect id="second-effect"><profile_COMMON>)" + samplerAndSurface("again") +
        R"(<technique sid="common"><phong><diffuse><texture texture="tex-sampler" texcoord="UV0"/>
                     </diffuse></phong></technique></profile_COMMON></effect>)";
    d.extraMaterials =
        R"(<material id="second" name="second"><instance_effect url="#second-effect"/></material>)";
    std::string text = xml(d);
    // A second instance of the square bound to the second material.
    const std::string node = R"(<node id="Square" name="Square">)";
    const size_t at = text.find(node);
    ASSERT_NE(at, std::string::npos);
    text.insert(
        at,
        R"(<node id="Second" name="Second"><translate>2 0 0</translate><instance_geometry url="#square">
        <bind_material><technique_common><instance_material symbol="textured" target="#second"/>
        </technique_common></bind_material></instance_geometry></node>)");
    const scene::Scene s = load(dir.write("twice.dae", text));
    ASSERT_EQ(s.meshes.size(), 2u);
    EXPECT_NE(s.meshes[0].material, s.meshes[1].material);
    EXPECT_EQ(s.images.size(), 1u);
    EXPECT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(std::count(s.referencedFiles.begin(), s.referencedFiles.end(), dir / "tex.png"), 1);
}

// Bad references are one line naming the .dae and what is wrong, as the
// glTF importer's are (gltf::uriProblem is the rule for both).
TEST(ColladaTextures, BadImageReferencesAreOneErrorLine) {
    TempDir dir;
    fs::create_directories(dir / "scene");
    writeTestPng(dir / "outside.png");
    fs::create_symlink("../outside.png", dir / "scene" / "link.png");
    struct Case {
        std::string uri, problem;
    };
    const std::vector<Case> cases = {
        {"missing.png", "names a file that does not exist"},
        {"../outside.png", "leaves the scene's folder"},
        {"sub/%2E%2E/../outside.png", "leaves the scene's folder"},
        {(dir / "outside.png").string(), "is an absolute path"},
        {"file:///tmp/outside.png", "has a scheme"},
        {"C:\\textures\\wood.png", "has a scheme or drive"},
        {"link.png", "leaves the scene's folder through a link"},
        {"line\nbreak.png", "contains control characters"},
    };
    for (const Case& c : cases) {
        Doc d;
        d.images = R"(<image id="tex" name="tex"><init_from>)" + c.uri + "</init_from></image>";
        const fs::path file = dir.write("scene/bad.dae", xml(d));
        const std::string error = loadError(file);
        EXPECT_EQ(error.rfind(file.string() + ": material 'textured': image 'tex': uri '", 0), 0u)
            << error;
        EXPECT_NE(error.find(c.problem), std::string::npos) << c.uri << ": " << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << "one line: " << error;
    }

    Doc dataUri;
    dataUri.images =
        R"(<image id="tex" name="tex"><init_from>data:image/png;base64,iVBORw0KGgo=</init_from></image>)";
    const std::string data = loadError(dir.write("scene/data.dae", xml(dataUri)));
    EXPECT_NE(data.find("image 'tex': data: URIs are not read from COLLADA"), std::string::npos)
        << data;

    Doc noImage;
    noImage.newparams = "";
    noImage.diffuse = R"(<texture texture="nosuch" texcoord="UV0"/>)";
    const std::string missingId = loadError(dir.write("scene/noimage.dae", xml(noImage)));
    EXPECT_NE(missingId.find("<texture texture=\"nosuch\">: missing referenced image id 'nosuch'"),
              std::string::npos)
        << missingId;

    Doc noSurface;
    noSurface.newparams =
        R"(<newparam sid="tex-sampler"><sampler2D><source>gone</source></sampler2D></newparam>)";
    const std::string surface = loadError(dir.write("scene/nosurface.dae", xml(noSurface)));
    EXPECT_NE(surface.find("<source> 'gone' names no <surface> newparam"), std::string::npos)
        << surface;
}

TEST(ColladaTextures, CommandLineRefusesAMissingImageWithOneLineAndWritesNothing) {
    TempDir dir;
    Doc d;
    d.images = R"(<image id="tex" name="tex"><init_from>missing.png</init_from></image>)";
    const fs::path file = dir.write("missing.dae", xml(d));
    const test::CommandResult r = test::runVkpath(
        "render '" + file.string() + "' -d 8x6 -s 1 -o '" + (dir / "out.exr").string() + "'", 60);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("vkpath: " + file.string() + ": ", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

TEST(ColladaTextures, AnImageThatCannotBeDecodedIsAWarningAndGrey) {
    TempDir dir;
    dir.write("tex.png", "not an image");
    std::vector<std::string> warnings;
    const scene::Scene s = load(dir.write("undecodable.dae", xml(Doc())), &warnings);
    EXPECT_TRUE(
        anyContains(warnings, "images that cannot be decoded (png) leave their textures out"))
        << (warnings.empty() ? "" : warnings[0]);
    const scene::Material& m = squareMaterial(s);
    EXPECT_FALSE(m.baseColorTexture.present());
    EXPECT_EQ(m.reflectance, glm::vec3(0.5f)) << "Scotty3D's grey, as without a colour";
    EXPECT_TRUE(s.images.empty());
}

TEST(ColladaTextures, OnlyImagesThatMaterialsUseAreRead) {
    TempDir dir;
    writeTestPng(dir / "tex.png");
    Doc d;
    d.images +=
        R"(<image id="unused" name="unused"><init_from>../../nowhere.png</init_from></image>)";
    const scene::Scene s = load(dir.write("unused.dae", xml(d)));
    EXPECT_EQ(s.images.size(), 1u);
}

TEST(ColladaTextures, APlusInAFileNameIsAPlus) {
    TempDir dir;
    writeTestPng(dir / "a+b.png");
    Doc d;
    d.images = R"(<image id="tex" name="tex"><init_from>a+b.png</init_from></image>)";
    const scene::Scene s = load(dir.write("plus.dae", xml(d)));
    EXPECT_EQ(s.images.size(), 1u);
}

TEST(ColladaTextures, ATexturedMeshWithoutCoordinatesIsWarnedAbout) {
    TempDir dir;
    writeTestPng(dir / "tex.png");
    Doc d;
    d.texcoords = false;
    std::vector<std::string> warnings;
    load(dir.write("nouv.dae", xml(d)), &warnings);
    EXPECT_TRUE(
        anyContains(warnings, "textured meshes without texture coordinates take one texel"));
}

// ---------------------------------------------------------------------------
// The duck of assimp-testmodels
// ---------------------------------------------------------------------------

#define SKIP_WITHOUT_PACKAGE()          \
    if (!fs::is_directory(DUCK_FOLDER)) \
    GTEST_SKIP()                        \
        << DUCK_FOLDER                  \
        << " is missing: Debian's assimp-testmodels is not installed (tools/install-deps)"

TEST(ColladaDuck, TextureIsTheTgasTexels) {
    SKIP_WITHOUT_PACKAGE();
    std::vector<std::string> warnings;
    const scene::Scene s = load(DUCK_FOLDER / "duck.dae", &warnings);
    EXPECT_FALSE(anyContains(warnings, "textur"));
    ASSERT_EQ(s.images.size(), 1u);
    ASSERT_EQ(s.textures.size(), 1u);
    for (const scene::Mesh& m : s.meshes) {
        EXPECT_EQ(s.materials.at(m.material).baseColorTexture.texture, 0);
        EXPECT_EQ(m.texcoords0.size(), m.positions.size());
    }
    const test::Texels tga = test::readTexels(DUCK_FOLDER / "duckCM.tga");
    ASSERT_EQ(int(s.images[0].width), tga.width);
    ASSERT_EQ(int(s.images[0].height), tga.height);
    size_t different = 0;
    for (size_t i = 0; i < s.images[0].texels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            different += s.images[0].texels[i][c] != tga.rgb[i * 3 + size_t(c)] * 257;
    EXPECT_EQ(different, 0u)
        << "texel channels that differ from OpenImageIO's reading of duckCM.tga";
}

// The duck's own texture on a square seen head-on under a white sky (the
// argument of BoxTextured in tests/corpus/textured_models_test.cpp: a flat
// diffuse face sees only the sky, so it reflects its albedo, and its texture
// coordinates cover the image once): the face's mean is the TGA's texels'
// mean, sRGB-decoded. The .dae is written by the test beside a copy of
// duckCM.tga in a temporary folder.
TEST(ColladaDuck, SquareWearingTheDucksTextureShowsItsMeanColour) {
    SKIP_WITHOUT_PACKAGE();
    TempDir dir;
    fs::copy_file(DUCK_FOLDER / "duckCM.tga", dir / "duckCM.tga");
    Doc d;
    d.images = R"(<image id="file2" name="file2"><init_from>./duckCM.tga</init_from></image>)";
    d.newparams = samplerAndSurface("file2");
    const fs::path file = dir.write("square.dae", xml(d));
    constexpr uint32_t W = 64, H = 48;

    const scene::Scene s = load(file);
    const shared::Camera camera = scene::makeGpuCamera(s.camera, W, H);
    ASSERT_NEAR(camera.origin.x, 0.0f, 1e-5f);  // Scotty3D's framing: on the axis, looking along -z
    ASSERT_NEAR(camera.origin.y, 0.0f, 1e-5f);
    ASSERT_NEAR(camera.forward.z, -1.0f, 1e-6f);
    const glm::dvec2 lo = test::project(camera, {-0.5, 0.5, 0.0}),
                     hi = test::project(camera, {0.5, -0.5, 0.0});

    const test::Render r = test::renderOnWhiteSky(file, W, H, 64, dir.path());
    ASSERT_EQ(r.image.width, W);
    const test::FaceMean face = test::faceMeanOnWhiteSky(r, lo, hi);
    ASSERT_TRUE(face.inside);
    ASSERT_GT(face.area, 500.0);

    const test::Texels tga = test::readTexels(DUCK_FOLDER / "duckCM.tga");
    const glm::dvec3 expected = test::meanTexel(tga, test::srgbToLinear);
    const glm::dvec3 undecoded = test::meanTexel(tga, [](double v) { return v; });
    double power = 0;
    for (int c = 0; c < 3; ++c) {
        // 5 standard errors, plus the texel store's half-float rounding (2^-11).
        const double bound = 5.0 * face.standardError[c] + std::ldexp(expected[c], -11);
        EXPECT_NEAR(face.mean[c], expected[c], bound)
            << "channel " << c << ", standard error " << face.standardError[c];
        power = std::max(power, std::abs(face.mean[c] - undecoded[c]) / bound);
    }
    // Power: the duck is saturated yellow, red near 1 and blue near 0, where
    // sRGB decoding changes little; in green the undecoded mean is far off.
    EXPECT_GT(power, 4.0) << "the texels' mean without sRGB decoding would pass too";
}

// duck.dae itself, end to end: its pixels (those that are not the sky, 1 in
// every channel) are the texture's colour. With a grey sky and a white
// light, a pixel's channels are in the ratio of the albedo's there, so the
// ratios of the pixels' channel means are the texture's, weighted by where
// the camera sees the duck and how it is lit rather than by texel: measured
// g/r 0.641 and b/r 0.0669 against the texels' 0.657 and 0.0661 (the duck is
// almost all one yellow). The bound, 15%, allows for that weighting; the
// untextured grey duck of before would be off by 50% and 1400%.
TEST(ColladaDuck, RendersInTheTexturesColours) {
    SKIP_WITHOUT_PACKAGE();
    const TempDir dir;
    const test::Render r = test::renderOnWhiteSky(DUCK_FOLDER / "duck.dae", 64, 48, 8, dir.path());
    ASSERT_EQ(r.image.width, 64u);
    glm::dvec3 sum(0.0);
    size_t duck = 0;
    for (const glm::vec3& p : r.image.pixels)
        if (p != glm::vec3(1.0f)) {
            sum += glm::dvec3(p);
            ++duck;
        }
    ASSERT_GT(duck, 300u) << "the duck covers about 470 of the 3072 pixels";
    const glm::dvec3 texels =
        test::meanTexel(test::readTexels(DUCK_FOLDER / "duckCM.tga"), test::srgbToLinear);
    EXPECT_NEAR(sum.y / sum.x, texels.y / texels.x, 0.15 * texels.y / texels.x);
    EXPECT_NEAR(sum.z / sum.x, texels.z / texels.x, 0.15 * texels.z / texels.x);
}

}  // namespace
