// Writes the seeds that the fuzz scripts cannot copy from the project:
//
//   fuzz_seeds ENV_DIR GLTF_DIR [COLLADA_DIR]
//
// ENV_DIR: small environment maps in every OpenEXR compression OpenImageIO
// writes (half and float, scanline and tiled, 1, 3 and 4 channels, a negative
// and a non-finite texel), plus Radiance .hdr files, so the mutations start
// from each decoder's format.
// GLTF_DIR: glTF files that use the fuzz folder's buffer.bin (fuzz_support.h)
// through a URI that stays inside the folder, and through each kind of URI
// that leaves it (a link, a linked folder, "..", "%2e%2e", an absolute path,
// a scheme), so every run exercises the folder rule; and a glTF whose
// triangle carries every vertex attribute the importer reads, in the
// quantized encodings of KHR_mesh_quantization, so the fuzzer starts inside
// those accessors.
// COLLADA_DIR: a textured square whose <image> is the fuzz folder's
// texture.png, or buffer.bin (not an image), or a file through each kind of
// URI that leaves the folder, so collada_fuzz starts inside the texture
// resolution and the folder rule.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "support/base64.h"

namespace {

namespace fs = std::filesystem;
using vkpath::test::base64;

struct MapSpec {
    std::string name;
    int width = 8, height = 4, channels = 3;
    OIIO::TypeDesc type = OIIO::TypeDesc::HALF;
    std::string compression = "none";
    int tile = 0;          // 0: scanlines
    float special = 0.0f;  // written into texel 0 when not 0
};

bool writeMap(const fs::path& path, const MapSpec& m) {
    std::vector<float> pixels(size_t(m.width) * m.height * m.channels);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = 0.05f * float(i % 37) + 0.01f;
    if (m.special != 0.0f) pixels[0] = m.special;
    OIIO::ImageSpec spec(m.width, m.height, m.channels, m.type);
    if (path.extension() == ".exr") spec.attribute("compression", m.compression);
    if (m.tile > 0) {
        spec.tile_width = m.tile;
        spec.tile_height = m.tile;
    }
    auto out = OIIO::ImageOutput::create(path.string());
    const bool ok = out && out->open(path.string(), spec) &&
                    out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close();
    if (!ok)
        std::fprintf(stderr, "fuzz_seeds: %s: %s\n", path.c_str(),
                     out ? out->geterror().c_str() : OIIO::geterror().c_str());
    return ok;
}

// Two parts (the environment loader reads the first): headers in sequence.
bool writeMultipart(const fs::path& path) {
    std::vector<OIIO::ImageSpec> specs(2, OIIO::ImageSpec(8, 4, 3, OIIO::TypeDesc::HALF));
    specs[1].width = 4;  // parts share the display window, not the data window
    for (size_t i = 0; i < specs.size(); ++i)
        specs[i].attribute("oiio:subimagename", fmt::format("part{}", i));
    std::vector<float> pixels(8 * 4 * 3, 0.25f);
    auto out = OIIO::ImageOutput::create(path.string());
    bool ok = out && out->open(path.string(), int(specs.size()), specs.data()) &&
              out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) &&
              out->open(path.string(), specs[1], OIIO::ImageOutput::AppendSubimage) &&
              out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close();
    if (!ok)
        std::fprintf(stderr, "fuzz_seeds: %s: %s\n", path.c_str(),
                     out ? out->geterror().c_str() : OIIO::geterror().c_str());
    return ok;
}

void writeText(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// One triangle from buffer.bin under `uri`, optionally with an image URI too.
std::string gltfWithBuffer(const std::string& uri, const std::string& imageUri = {}) {
    using vkpath::fuzz::BUFFER_BYTES;
    using vkpath::fuzz::BUFFER_INDICES_OFFSET;
    using vkpath::fuzz::BUFFER_POSITIONS_OFFSET;
    const std::string images =
        imageUri.empty() ? "" : fmt::format(R"(,"images":[{{"uri":"{}"}}])", imageUri);
    return fmt::format(
        R"({{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],)"
        R"("nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},)"
        R"("indices":1,"mode":4}}]}}],"accessors":[)"
        R"({{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",)"
        R"("min":[0,0,0],"max":[1,1,0]}},)"
        R"({{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}}],)"
        R"("bufferViews":[{{"buffer":0,"byteOffset":{},"byteLength":36}},)"
        R"({{"buffer":0,"byteOffset":{},"byteLength":6}}],)"
        R"("buffers":[{{"uri":"{}","byteLength":{}}}]{}}})",
        BUFFER_POSITIONS_OFFSET, BUFFER_INDICES_OFFSET, uri, BUFFER_BYTES, images);
}

// One triangle with quantized positions (u16), normals (normalized i8),
// TEXCOORD_0 (normalized u8), TEXCOORD_1 (i16), COLOR_0 (normalized u16
// RGBA) and TANGENT (normalized i8), each in a bufferView of its own with
// 4-byte-aligned elements, in an embedded buffer.
std::string gltfWithAttributes() {
    std::vector<uint8_t> bin;
    std::vector<std::string> views, accessors;
    auto add = [&](const std::vector<int>& values, size_t bytes, size_t width, int componentType,
                   const char* type, bool normalized) {
        const size_t element = width * bytes, stride = (element + 3) / 4 * 4;
        const size_t offset = bin.size();
        bin.resize(offset + stride * (values.size() / width), 0);
        for (size_t i = 0; i < values.size(); ++i)
            for (size_t b = 0; b < bytes; ++b)  // little-endian, two's complement
                bin[offset + (i / width) * stride + (i % width) * bytes + b] =
                    uint8_t(uint32_t(values[i]) >> (8 * b));
        views.push_back(fmt::format(
            R"({{"buffer":0,"byteOffset":{},"byteLength":{}{}}})", offset, bin.size() - offset,
            stride == element ? "" : fmt::format(R"(,"byteStride":{})", stride)));
        accessors.push_back(fmt::format(
            R"({{"bufferView":{},"componentType":{},"type":"{}","count":{}{}}})", views.size() - 1,
            componentType, type, values.size() / width, normalized ? R"(,"normalized":true)" : ""));
    };
    add({0, 0, 0, 1, 0, 0, 0, 1, 0}, 2, 3, 5123, "VEC3", false);
    add({0, 0, 127, 0, 0, 127, 0, 0, 127}, 1, 3, 5120, "VEC3", true);
    add({0, 255, 255, 255, 0, 0}, 1, 2, 5121, "VEC2", true);
    add({0, 0, 2, 0, 0, -2}, 2, 2, 5122, "VEC2", false);
    add({65535, 0, 0, 65535, 0, 65535, 0, 32768, 0, 0, 65535, 65535}, 2, 4, 5123, "VEC4", true);
    add({127, 0, 0, 127, 127, 0, 0, -127, 0, 127, 0, 127}, 1, 4, 5120, "VEC4", true);
    add({0, 1, 2}, 2, 1, 5123, "SCALAR", false);
    std::string viewList, accessorList;
    for (const std::string& v : views) viewList += (viewList.empty() ? "" : ",") + v;
    for (const std::string& a : accessors) accessorList += (accessorList.empty() ? "" : ",") + a;
    return fmt::format(
        R"({{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_mesh_quantization"],)"
        R"("extensionsRequired":["KHR_mesh_quantization"],"scene":0,"scenes":[{{"nodes":[0]}}],)"
        R"("nodes":[{{"mesh":0,"scale":[0.5,0.5,0.5]}}],"meshes":[{{"primitives":[{{)"
        R"("attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2,"TEXCOORD_1":3,"COLOR_0":4,)"
        R"("TANGENT":5}},"indices":6,"mode":4}}]}}],"accessors":[{}],"bufferViews":[{}],)"
        R"("buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]}})",
        accessorList, viewList, bin.size(), base64(bin));
}

// A 4 x 4 RGBA PNG (OpenImageIO writes it to `scratch`, which is removed).
std::vector<uint8_t> smallPng(const fs::path& scratch) {
    std::vector<uint8_t> pixels(4 * 4 * 4);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = uint8_t(i * 37);
    auto out = OIIO::ImageOutput::create(scratch.string());
    if (!out || !out->open(scratch.string(), OIIO::ImageSpec(4, 4, 4, OIIO::TypeDesc::UINT8)) ||
        !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
        return {};
    std::ifstream in(scratch, std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    fs::remove(scratch);
    return bytes;
}

// The vertex-attribute triangle with a textured material: a data-URI PNG as
// base colour (read from TEXCOORD_1 through KHR_texture_transform) and
// emissive texture, a sampler with two wrap modes and nearest filtering.
std::string gltfWithTexture(const std::vector<uint8_t>& png) {
    std::string gltf = gltfWithAttributes();
    const std::string primitiveEnd = R"("indices":6,"mode":4})";
    gltf.replace(gltf.find(primitiveEnd), primitiveEnd.size(),
                 R"("indices":6,"mode":4,"material":0})");
    gltf.replace(gltf.find(R"("extensionsUsed":["KHR_mesh_quantization"])"),
                 std::string(R"("extensionsUsed":["KHR_mesh_quantization"])").size(),
                 R"("extensionsUsed":["KHR_mesh_quantization","KHR_texture_transform"])");
    gltf.pop_back();  // the closing brace
    gltf += fmt::format(
        R"(,"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0,"texCoord":1,)"
        R"("extensions":{{"KHR_texture_transform":{{"offset":[0.5,0],"rotation":0.3,"scale":[2,2]}}}}}}}},)"
        R"("emissiveTexture":{{"index":0}},"emissiveFactor":[1,1,1]}}],)"
        R"("textures":[{{"source":0,"sampler":0}}],"samplers":[{{"wrapS":33648,"wrapT":33071,"magFilter":9728}}],)"
        R"("images":[{{"uri":"data:image/png;base64,{}"}}]}})",
        base64(png));
    return gltf;
}

// A unit square with texture coordinates whose diffuse texture is the file
// `uri`, through duck.dae's sampler2D and surface newparams.
std::string colladaWithTexture(const std::string& uri) {
    return fmt::format(R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><up_axis>Y_UP</up_axis></asset>
<library_images><image id="img" name="img"><init_from>{}</init_from></image></library_images>
<library_effects><effect id="fx"><profile_COMMON>
<newparam sid="surface"><surface type="2D"><init_from>img</init_from></surface></newparam>
<newparam sid="sampler"><sampler2D><source>surface</source><wrap_s>MIRROR</wrap_s><wrap_t>CLAMP</wrap_t>
<magfilter>NEAREST</magfilter></sampler2D></newparam>
<technique sid="common"><lambert><diffuse><texture texture="sampler" texcoord="UV"/></diffuse></lambert>
</technique></profile_COMMON></effect></library_effects>
<library_materials><material id="mat" name="mat"><instance_effect url="#fx"/></material></library_materials>
<library_geometries><geometry id="square"><mesh>
<source id="p"><float_array id="pa" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"/></technique_common></source>
<source id="t"><float_array id="ta" count="8">0 0 1 0 1 1 0 1</float_array>
<technique_common><accessor source="#ta" count="4" stride="2"/></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles material="mat" count="2"><input semantic="VERTEX" source="#v" offset="0"/>
<input semantic="TEXCOORD" source="#t" offset="1" set="0"/><p>0 0 1 1 2 2 0 0 2 2 3 3</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#square"><bind_material>
<technique_common><instance_material symbol="mat" target="#mat"/></technique_common></bind_material>
</instance_geometry></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)",
                       uri);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3 && argc != 4) {
        std::fprintf(stderr, "usage: fuzz_seeds ENV_DIR GLTF_DIR [COLLADA_DIR]\n");
        return 2;
    }
    const fs::path envDir = argv[1], gltfDir = argv[2];
    fs::create_directories(envDir);
    fs::create_directories(gltfDir);

    const float inf = std::numeric_limits<float>::infinity();
    std::vector<MapSpec> maps;
    for (const char* c :
         {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"})
        maps.push_back({.name = fmt::format("half_{}.exr", c), .compression = c});
    maps.push_back({.name = "float_zip.exr", .type = OIIO::TypeDesc::FLOAT, .compression = "zip"});
    maps.push_back({.name = "float_piz_tiled.exr",
                    .width = 16,
                    .height = 8,
                    .type = OIIO::TypeDesc::FLOAT,
                    .compression = "piz",
                    .tile = 4});
    maps.push_back({.name = "half_grey.exr", .channels = 1, .compression = "zips"});
    maps.push_back(
        {.name = "half_rgba_rle_tiled.exr", .channels = 4, .compression = "rle", .tile = 4});
    maps.push_back({.name = "half_negative.exr", .special = -1.0f});
    maps.push_back({.name = "float_infinite.exr", .type = OIIO::TypeDesc::FLOAT, .special = inf});
    maps.push_back({.name = "small.hdr", .type = OIIO::TypeDesc::FLOAT});
    maps.push_back({.name = "wide.hdr", .width = 64, .height = 2, .type = OIIO::TypeDesc::FLOAT});
    bool ok = true;
    for (const MapSpec& m : maps) ok = writeMap(envDir / m.name, m) && ok;
    ok = writeMultipart(envDir / "multipart.exr") && ok;

    writeText(gltfDir / "buffer_inside.gltf", gltfWithBuffer("buffer.bin"));
    writeText(gltfDir / "buffer_encoded.gltf", gltfWithBuffer("buffer%2ebin"));
    writeText(gltfDir / "escape_link.gltf", gltfWithBuffer("escape.bin"));
    writeText(gltfDir / "escape_linked_dir.gltf", gltfWithBuffer("escape_dir/buffer.bin"));
    writeText(gltfDir / "escape_dotdot.gltf", gltfWithBuffer("../outside/buffer.bin"));
    writeText(gltfDir / "escape_dotdot_encoded.gltf", gltfWithBuffer("%2e%2e/outside/buffer.bin"));
    writeText(gltfDir / "escape_backslash.gltf", gltfWithBuffer("..\\\\outside\\\\buffer.bin"));
    writeText(gltfDir / "escape_absolute.gltf", gltfWithBuffer("/etc/hostname"));
    writeText(gltfDir / "escape_scheme.gltf", gltfWithBuffer("file:///etc/hostname"));
    writeText(gltfDir / "escape_image.gltf", gltfWithBuffer("buffer.bin", "escape_dir/secret.txt"));
    writeText(gltfDir / "vertex_attributes.gltf", gltfWithAttributes());
    const std::vector<uint8_t> png = smallPng(gltfDir / "scratch.png");
    ok = !png.empty() && ok;
    writeText(gltfDir / "textured.gltf", gltfWithTexture(png));
    if (argc == 4) {
        const fs::path colladaDir = argv[3];
        fs::create_directories(colladaDir);
        writeText(colladaDir / "textured.dae", colladaWithTexture(vkpath::fuzz::TEXTURE_PNG));
        writeText(colladaDir / "texture_not_an_image.dae", colladaWithTexture("./buffer.bin"));
        writeText(colladaDir / "texture_escape_link.dae", colladaWithTexture("escape.bin"));
        writeText(colladaDir / "texture_escape_linked_dir.dae",
                  colladaWithTexture("escape_dir/secret.txt"));
        writeText(colladaDir / "texture_escape_dotdot.dae",
                  colladaWithTexture("../outside/buffer.bin"));
        writeText(colladaDir / "texture_escape_encoded.dae",
                  colladaWithTexture("%2e%2e/outside/buffer.bin"));
        writeText(colladaDir / "texture_escape_absolute.dae", colladaWithTexture("/etc/hostname"));
        writeText(colladaDir / "texture_escape_scheme.dae",
                  colladaWithTexture("file:///etc/hostname"));
    }
    return ok ? 0 : 1;
}
