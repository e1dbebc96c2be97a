// The glTF importer's material extensions (host/scene/gltf_materials.cpp):
// the layers over the metallic-roughness material (KHR_materials_clearcoat
// and KHR_materials_sheen: their factors, their textures and what is warned
// about or refused), diffuse transmission, thin films, anisotropy and
// thin-walled transmission.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

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

// One triangle of a material with `extensions` over a base of `pbr`, with a
// 1 x 1 white PNG beside the file as texture 0 for the layers' textures to name.
fs::path layeredTriangle(const fs::path& file, const Json& extensions,
                         const Json& pbr = {{"metallicFactor", 0}}) {
    const fs::path image = file.parent_path() / "white.png";
    const uint8_t white[3] = {255, 255, 255};
    auto out = OIIO::ImageOutput::create(image.string());
    EXPECT_TRUE(out && out->open(image.string(), OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::UINT8)) &&
                out->write_image(OIIO::TypeDesc::UINT8, white) && out->close());
    GltfBuilder g;
    g.doc["images"] = {{{"uri", "white.png"}}};
    g.doc["textures"] = {{{"source", 0}}};
    const int m = g.material({{"pbrMetallicRoughness", pbr}, {"extensions", extensions}});
    g.node({{"mesh", g.triangle(m)}});
    g.camera();
    return g.writeGltf(file);
}

TEST(GltfLayers, ClearcoatAndSheenFactorsAndTextures) {
    TempDir dir;
    const auto loaded = load(layeredTriangle(
        dir / "extensions.gltf",
        {{"KHR_materials_clearcoat",
          {{"clearcoatFactor", 0.7},
           {"clearcoatRoughnessFactor", 0.2},
           {"clearcoatTexture", {{"index", 0}}},
           {"clearcoatRoughnessTexture",
            {{"index", 0},
             {"texCoord", 1},
             {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0.25}}}}}}}}}},
         {"KHR_materials_sheen",
          {{"sheenColorFactor", {0.9, 0.5, 0.1}},
           {"sheenRoughnessFactor", 0.4},
           {"sheenColorTexture", {{"index", 0}}},
           {"sheenRoughnessTexture", {{"index", 0}}}}}}));
    EXPECT_EQ(loaded.warnings, "");
    const scene::Material& m = loaded.scene.materials.at(0);
    EXPECT_EQ(m.kind, scene::MaterialKind::MetallicRoughness);
    EXPECT_FLOAT_EQ(m.clearcoat, 0.7f);
    EXPECT_FLOAT_EQ(m.clearcoatRoughness, 0.2f);
    EXPECT_EQ(m.sheenColor, glm::vec3(0.9f, 0.5f, 0.1f));
    EXPECT_FLOAT_EQ(m.sheenRoughness, 0.4f);
    EXPECT_EQ(m.clearcoatTexture.texture, 0);
    EXPECT_EQ(m.clearcoatRoughnessTexture.texture, 0);
    EXPECT_EQ(m.clearcoatRoughnessTexture.texCoord, 1u);
    EXPECT_EQ(m.clearcoatRoughnessTexture.offset, glm::vec2(0.5f, 0.25f));
    EXPECT_EQ(m.sheenColorTexture.texture, 0);
    EXPECT_EQ(m.sheenRoughnessTexture.texture, 0);
}

// A layer keeps glTF's metal and its non-metal without a specular layer in
// the layered kind (the conductor and the Lambertian have no layers); a
// layer of factor 0 is none, its texture dropped; the defaults are no layer.
TEST(GltfLayers, ALayerKeepsTheLayeredKind) {
    TempDir dir;
    const auto metal = load(layeredTriangle(dir / "metal.gltf",
                                            {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1}}}},
                                            {{"metallicFactor", 1}}));
    EXPECT_EQ(metal.scene.materials.at(0).kind, scene::MaterialKind::MetallicRoughness);
    const auto matte = load(layeredTriangle(
        dir / "matte.gltf", {{"KHR_materials_sheen", {{"sheenColorFactor", {1, 1, 1}}}},
                             {"KHR_materials_specular", {{"specularFactor", 0}}}}));
    EXPECT_EQ(matte.scene.materials.at(0).kind, scene::MaterialKind::MetallicRoughness);
    const auto none =
        load(layeredTriangle(dir / "none.gltf",
                             {{"KHR_materials_clearcoat", {{"clearcoatTexture", {{"index", 0}}}}},
                              {"KHR_materials_sheen", {{"sheenRoughnessFactor", 0.5}}}},
                             {{"metallicFactor", 1}}));
    const scene::Material& m = none.scene.materials.at(0);
    EXPECT_EQ(m.kind, scene::MaterialKind::Conductor);
    EXPECT_EQ(m.clearcoat, 0.0f);
    EXPECT_EQ(m.sheenColor, glm::vec3(0.0f));
    EXPECT_FALSE(m.clearcoatTexture.present());
}

// Warned: factors outside [0, 1] (clamped), layers on glass (dropped).
// Read: the coat's own normal map and its scale. Refused in one line naming
// the file and material: a factor that is not a number, a texture that is
// not a textureInfo, a texture index out of range, a coat normal map's scale
// that is not a number.
TEST(GltfLayers, WarningsAndErrors) {
    TempDir dir;
    const auto clamped = load(
        layeredTriangle(dir / "clamped.gltf",
                        {{"KHR_materials_clearcoat",
                          {{"clearcoatFactor", 2}, {"clearcoatNormalTexture", {{"index", 0}}}}}}));
    EXPECT_EQ(clamped.scene.materials.at(0).clearcoat, 1.0f);
    EXPECT_CONTAINS(clamped.warnings, "material factors outside [0, 1] are clamped");
    EXPECT_EQ(clamped.scene.materials.at(0).clearcoatNormalTexture.texture, 0);
    const auto scaled = load(layeredTriangle(
        dir / "scaled.gltf",
        {{"KHR_materials_clearcoat",
          {{"clearcoatFactor", 1}, {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.5}}}}}}));
    EXPECT_FLOAT_EQ(scaled.scene.materials.at(0).clearcoatNormalScale, 0.5f);
    EXPECT_CONTAINS(loadError(layeredTriangle(
                        dir / "unscaled.gltf",
                        {{"KHR_materials_clearcoat",
                          {{"clearcoatFactor", 1},
                           {"clearcoatNormalTexture", {{"index", 0}, {"scale", "half"}}}}}})),
                    "clearcoatNormalTexture.scale is not a finite number");
    EXPECT_EQ(clamped.warnings.find("textures of material extensions"), std::string::npos)
        << clamped.warnings;

    const auto glass = load(layeredTriangle(
        dir / "glass.gltf", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                             {"KHR_materials_volume", {{"thicknessFactor", 1}}},
                             {"KHR_materials_sheen", {{"sheenColorFactor", {1, 1, 1}}}}}));
    EXPECT_EQ(glass.scene.materials.at(0).sheenColor, glm::vec3(0.0f));
    EXPECT_CONTAINS(glass.warnings, "of transmissive materials are ignored");

    EXPECT_CONTAINS(loadError(layeredTriangle(dir / "nan.gltf", {{"KHR_materials_clearcoat",
                                                                  {{"clearcoatFactor", "x"}}}})),
                    "KHR_materials_clearcoat.clearcoatFactor is not a number");
    EXPECT_CONTAINS(
        loadError(layeredTriangle(dir / "info.gltf",
                                  {{"KHR_materials_sheen",
                                    {{"sheenColorFactor", {1, 1, 1}}, {"sheenColorTexture", 3}}}})),
        "KHR_materials_sheen.sheenColorTexture is not a textureInfo");
    const std::string range = loadError(layeredTriangle(
        dir / "range.gltf",
        {{"KHR_materials_clearcoat",
          {{"clearcoatFactor", 1}, {"clearcoatRoughnessTexture", {{"index", 5}}}}}}));
    EXPECT_CONTAINS(range, "range.gltf");
    EXPECT_CONTAINS(range, "clearcoatRoughnessTexture names texture 5, of 1");
}

// KHR_materials_diffuse_transmission: its share and colour with their
// textures; it keeps a non-metal without a specular layer in the layered
// kind (the Lambertian has no back); a volume beside it is warned about
// (vkpath's diffuse transmission is thin-walled).
TEST(GltfDiffuseTransmission, ShareColourAndTextures) {
    TempDir dir;
    const auto leaf = load(layeredTriangle(
        dir / "leaf.gltf", {{"KHR_materials_specular", {{"specularFactor", 0}}},
                            {"KHR_materials_diffuse_transmission",
                             {{"diffuseTransmissionFactor", 0.4},
                              {"diffuseTransmissionColorFactor", {0.5, 0.9, 0.1}},
                              {"diffuseTransmissionTexture", {{"index", 0}}},
                              {"diffuseTransmissionColorTexture", {{"index", 0}}}}}}));
    EXPECT_EQ(leaf.warnings, "");
    const scene::Material& m = leaf.scene.materials.at(0);
    EXPECT_EQ(m.kind, scene::MaterialKind::MetallicRoughness);
    EXPECT_FLOAT_EQ(m.diffuseTransmission, 0.4f);
    EXPECT_EQ(m.diffuseTransmissionColor, glm::vec3(0.5f, 0.9f, 0.1f));
    EXPECT_EQ(m.diffuseTransmissionTexture.texture, 0);
    EXPECT_EQ(m.diffuseTransmissionColorTexture.texture, 0);
    const auto thick = load(layeredTriangle(
        dir / "thick.gltf",
        {{"KHR_materials_volume", {{"thicknessFactor", 1}}},
         {"KHR_materials_diffuse_transmission", {{"diffuseTransmissionFactor", 1}}}}));
    EXPECT_EQ(thick.scene.materials.at(0).diffuseTransmissionColor, glm::vec3(1.0f));
    EXPECT_CONTAINS(thick.warnings, "KHR_materials_volume of diffuse-transmitting materials");
}

// KHR_materials_iridescence: weight, index, thickness range and textures
// (the defaults 1.3, 100 and 400 nm); an index or thickness that is not a
// finite number in range is one line naming it.
TEST(GltfIridescence, FilmIndexThicknessAndTextures) {
    TempDir dir;
    const auto filmed = load(layeredTriangle(dir / "film.gltf",
                                             {{"KHR_materials_iridescence",
                                               {{"iridescenceFactor", 0.8},
                                                {"iridescenceIor", 1.4},
                                                {"iridescenceThicknessMinimum", 200},
                                                {"iridescenceThicknessMaximum", 700},
                                                {"iridescenceTexture", {{"index", 0}}},
                                                {"iridescenceThicknessTexture", {{"index", 0}}}}}},
                                             {{"metallicFactor", 1}}));
    EXPECT_EQ(filmed.warnings, "");
    const scene::Material& m = filmed.scene.materials.at(0);
    EXPECT_EQ(m.kind, scene::MaterialKind::MetallicRoughness);
    EXPECT_FLOAT_EQ(m.iridescence, 0.8f);
    EXPECT_FLOAT_EQ(m.iridescenceIor, 1.4f);
    EXPECT_FLOAT_EQ(m.iridescenceThicknessMinimum, 200.0f);
    EXPECT_FLOAT_EQ(m.iridescenceThicknessMaximum, 700.0f);
    EXPECT_EQ(m.iridescenceTexture.texture, 0);
    EXPECT_EQ(m.iridescenceThicknessTexture.texture, 0);
    const auto defaults = load(layeredTriangle(
        dir / "defaults.gltf", {{"KHR_materials_iridescence", {{"iridescenceFactor", 1}}}}));
    EXPECT_FLOAT_EQ(defaults.scene.materials.at(0).iridescenceIor, 1.3f);
    EXPECT_FLOAT_EQ(defaults.scene.materials.at(0).iridescenceThicknessMinimum, 100.0f);
    EXPECT_FLOAT_EQ(defaults.scene.materials.at(0).iridescenceThicknessMaximum, 400.0f);
    EXPECT_CONTAINS(loadError(layeredTriangle(
                        dir / "ior.gltf", {{"KHR_materials_iridescence",
                                            {{"iridescenceFactor", 1}, {"iridescenceIor", 0}}}})),
                    "iridescenceIor 0 is not a finite number > 0");
    EXPECT_CONTAINS(loadError(layeredTriangle(
                        dir / "thick.gltf",
                        {{"KHR_materials_iridescence",
                          {{"iridescenceFactor", 1}, {"iridescenceThicknessMaximum", -5}}}})),
                    "iridescenceThicknessMaximum -5 is not a finite number >= 0");
}

// KHR_materials_anisotropy: the strength (clamped to [0, 1]), the rotation
// (any finite angle) and the texture, on the metallic-roughness material,
// the metal and rough glass; smooth glass with anisotropy becomes rough
// glass; a Lambertian material drops it. A mesh with the material and no
// texture coordinates (no tangent frame to turn the direction in) is warned
// about.
TEST(GltfAnisotropy, StrengthRotationTextureAndKinds) {
    TempDir dir;
    const Json brushed = {{"KHR_materials_anisotropy",
                           {{"anisotropyStrength", 0.6},
                            {"anisotropyRotation", 1.2},
                            {"anisotropyTexture", {{"index", 0}}}}}};
    for (const auto& [pbr, kind] :
         {std::pair{Json{{"metallicFactor", 1}, {"roughnessFactor", 0}},
                    scene::MaterialKind::Conductor},
          std::pair{Json{{"metallicFactor", 0.5}, {"roughnessFactor", 0.4}},
                    scene::MaterialKind::MetallicRoughness}}) {
        const auto loaded = load(layeredTriangle(dir / "brushed.gltf", brushed, pbr));
        const scene::Material& m = loaded.scene.materials.at(0);
        EXPECT_EQ(m.kind, kind);
        EXPECT_FLOAT_EQ(m.anisotropy, 0.6f);
        EXPECT_FLOAT_EQ(m.anisotropyRotation, 1.2f);
        EXPECT_EQ(m.anisotropyTexture.texture, 0);
        EXPECT_CONTAINS(loaded.warnings,
                        "anisotropic materials on meshes without texture "
                        "coordinates render isotropic");
    }
    Json glass = brushed;
    glass["KHR_materials_transmission"] = {{"transmissionFactor", 1}};
    const auto rough = load(layeredTriangle(dir / "glass.gltf", glass, {{"roughnessFactor", 0}}));
    EXPECT_EQ(rough.scene.materials.at(0).kind, scene::MaterialKind::RoughDielectric);
    EXPECT_FLOAT_EQ(rough.scene.materials.at(0).anisotropy, 0.6f);
    const auto lambertian = load(layeredTriangle(
        dir / "paper.gltf", {{"KHR_materials_anisotropy", {{"anisotropyStrength", 0.6}}},
                             {"KHR_materials_specular", {{"specularFactor", 0}}}}));
    EXPECT_EQ(lambertian.scene.materials.at(0).kind, scene::MaterialKind::Diffuse);
    EXPECT_EQ(lambertian.scene.materials.at(0).anisotropy, 0.0f);

    // With texture coordinates the frame is made from them: no warning.
    GltfBuilder g;
    const int m =
        g.material({{"pbrMetallicRoughness", {{"metallicFactor", 1}}},
                    {"extensions", {{"KHR_materials_anisotropy", {{"anisotropyStrength", 1.5}}}}}});
    g.node({{"mesh", g.uvSphere(8, true, m)}});
    g.camera();
    const auto sphere = load(g.writeGltf(dir / "sphere.gltf"));
    EXPECT_FLOAT_EQ(sphere.scene.materials.at(0).anisotropy, 1.0f);
    EXPECT_EQ(sphere.warnings.find("isotropic"), std::string::npos) << sphere.warnings;
    EXPECT_CONTAINS(sphere.warnings, "material factors outside [0, 1] are clamped");

    EXPECT_CONTAINS(
        loadError(layeredTriangle(dir / "turned.gltf",
                                  {{"KHR_materials_anisotropy",
                                    {{"anisotropyStrength", 1}, {"anisotropyRotation", "left"}}}})),
        "anisotropyRotation");
}

// KHR_materials_dispersion: read on glass with a volume (a solid), ignored
// with a warning on a thin wall, ignored silently on opaque materials (it
// changes volumetric refraction only); a negative factor is an error.
TEST(GltfDispersion, OnSolidGlassOnly) {
    TempDir dir;
    Json solid = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                  {"KHR_materials_volume", {{"thicknessFactor", 1}}},
                  {"KHR_materials_dispersion", {{"dispersion", 0.5}}}};
    const Json smooth = {{"metallicFactor", 0}, {"roughnessFactor", 0}};
    const auto glass = load(layeredTriangle(dir / "solid.gltf", solid, smooth));
    EXPECT_EQ(glass.warnings, "");
    EXPECT_EQ(glass.scene.materials.at(0).kind, scene::MaterialKind::Dielectric);
    EXPECT_FLOAT_EQ(glass.scene.materials.at(0).dispersion, 0.5f);
    Json thin = solid;
    thin.erase("KHR_materials_volume");
    const auto wall = load(layeredTriangle(dir / "thin.gltf", thin));
    EXPECT_EQ(wall.scene.materials.at(0).dispersion, 0.0f);
    EXPECT_CONTAINS(wall.warnings, "KHR_materials_dispersion without KHR_materials_volume");
    const auto opaque = load(layeredTriangle(
        dir / "opaque.gltf", {{"KHR_materials_dispersion", {{"dispersion", 0.5}}}}));
    EXPECT_EQ(opaque.scene.materials.at(0).dispersion, 0.0f);
    solid["KHR_materials_dispersion"]["dispersion"] = -1;
    EXPECT_CONTAINS(loadError(layeredTriangle(dir / "negative.gltf", solid)),
                    "dispersion -1 is not a finite number >= 0");
}

// KHR_materials_transmission without KHR_materials_volume is a thin wall
// (smooth or rough glass with no inside: its attenuation is dropped), with
// the volume a solid; neither is warned about.
TEST(GltfThinWalls, TransmissionWithoutAVolumeIsAThinWall) {
    TempDir dir;
    const Json transmission = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}};
    const auto thin = load(layeredTriangle(dir / "thin.gltf", transmission,
                                           {{"metallicFactor", 0}, {"roughnessFactor", 0.3}}));
    EXPECT_EQ(thin.warnings, "");
    EXPECT_EQ(thin.scene.materials.at(0).kind, scene::MaterialKind::RoughDielectric);
    EXPECT_TRUE(thin.scene.materials.at(0).thinWalled);
    Json withVolume = transmission;
    withVolume["KHR_materials_volume"] = {{"thicknessFactor", 1}};
    const auto solid = load(layeredTriangle(dir / "solid.gltf", withVolume,
                                            {{"metallicFactor", 0}, {"roughnessFactor", 0}}));
    EXPECT_EQ(solid.warnings, "");
    EXPECT_EQ(solid.scene.materials.at(0).kind, scene::MaterialKind::Dielectric);
    EXPECT_FALSE(solid.scene.materials.at(0).thinWalled);
}

}  // namespace
