// Inputs the loaders' fuzz harnesses (fuzz/, tools/fuzz-smoke) found, reduced
// to the bytes that matter and written here, each with what it broke. They
// run in the ordinary test build, without sanitizers: each checks that the
// input is refused with InputError (or read correctly) and no more.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "input_error.h"
#include "scene/environment.h"
#include "scene/load.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

namespace fs = std::filesystem;
using namespace vkpath;

using test::TempDir;

// ---------------------------------------------------------------------------
// A single-part scanline OpenEXR file, uncompressed, written byte by byte
// (OpenEXR file layout: magic, version, attributes, offset table, chunks).
// ---------------------------------------------------------------------------

constexpr int32_t EXR_HALF = 1, EXR_FLOAT = 2;

template <typename T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // little-endian host, as the format
    out.append(bytes, sizeof(T));
}

void attribute(std::string& out, const std::string& name, const std::string& type,
               const std::string& value) {
    out += name + '\0' + type + '\0';
    put(out, int32_t(value.size()));
    out += value;
}

std::string box(int32_t width, int32_t height) {
    std::string b;
    for (int32_t v : {0, 0, width - 1, height - 1}) put(b, v);
    return b;
}

// `channels` must be sorted, as OpenEXR stores them; `pixels` holds, per
// scanline, each channel's `width` floats in that order. Without pixels the
// offset table is all zeros: a header whose scanlines are missing.
// `extraAttributes` (name\0 type\0 size value) end the header.
std::string exr(int32_t width, int32_t height, const std::vector<std::string>& channels,
                int32_t pixelType, const std::vector<float>& pixels = {},
                const std::string& extraAttributes = {}) {
    std::string out;
    put(out, uint32_t(20000630));  // magic
    put(out, uint32_t(2));         // version 2, single-part scanline
    std::string list;
    for (const std::string& name : channels) {
        list += name + '\0';
        put(list, pixelType);
        put(list, uint32_t(0));  // pLinear, reserved
        put(list, int32_t(1));   // xSampling
        put(list, int32_t(1));   // ySampling
    }
    list += '\0';
    attribute(out, "channels", "chlist", list);
    attribute(out, "compression", "compression", std::string(1, '\0'));
    attribute(out, "dataWindow", "box2i", box(width, height));
    attribute(out, "displayWindow", "box2i", box(width, height));
    attribute(out, "lineOrder", "lineOrder", std::string(1, '\0'));
    std::string one, centre;
    put(one, 1.0f);
    put(centre, 0.0f);
    put(centre, 0.0f);
    attribute(out, "pixelAspectRatio", "float", one);
    attribute(out, "screenWindowCenter", "v2f", centre);
    attribute(out, "screenWindowWidth", "float", one);
    out += extraAttributes + '\0';

    if (pixels.empty()) {
        for (int32_t y = 0; y < height; ++y) put(out, uint64_t(0));
        return out;
    }
    const size_t lineFloats = size_t(width) * channels.size();
    const uint64_t chunkBytes = 8 + lineFloats * sizeof(float);
    const uint64_t firstChunk = out.size() + size_t(height) * sizeof(uint64_t);
    for (int32_t y = 0; y < height; ++y) put(out, firstChunk + uint64_t(y) * chunkBytes);
    for (int32_t y = 0; y < height; ++y) {
        put(out, y);
        put(out, int32_t(lineFloats * sizeof(float)));
        for (size_t i = 0; i < lineFloats; ++i) put(out, pixels[size_t(y) * lineFloats + i]);
    }
    return out;
}

// ---------------------------------------------------------------------------
// Environment maps
// ---------------------------------------------------------------------------

// environment_fuzz: a 29 KB EXR header declaring 1024 x 1024 texels of 1000
// half channels made readImage allocate width x height x channels floats
// (4 GB; the cap on pixels did not bound a pixel's size). At the default cap
// (8192 x 4096) 4096 channels asked for 512 GB: std::bad_alloc, not
// InputError. Only the three channels used are read now, so this header
// costs what an RGB map of its size does and is refused for its missing
// scanlines.
TEST(EnvironmentFuzzRegression, ThousandsOfChannelsDoNotMultiplyTheAllocation) {
    TempDir dir;
    std::vector<std::string> channels;
    for (int i = 0; i < 4096; ++i) channels.push_back(fmt::format("c{:04}", i));
    const fs::path path = dir.write("channels.exr", exr(8192, 4096, channels, EXR_HALF));
    try {
        scene::loadEnvironmentMap(path);
        ADD_FAILURE() << "a header without scanlines loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot read image"), std::string::npos) << e.what();
    }
}

// environment_fuzz: OpenEXR trusts an attribute's declared size. This 2 KB
// header (reduced: one string attribute claiming 1.7 GB, 5 bytes of it
// present) made OpenEXR allocate and zero 1.7 GB before failing with
// "Unexpected end of file". Attribute sizes are now checked against the file
// before OpenImageIO opens it (image::readImage).
TEST(EnvironmentFuzzRegression, AttributeLargerThanTheFileIsRefusedBeforeOpening) {
    TempDir dir;
    std::string capDate = std::string("capDate") + '\0' + "string" + '\0';
    put(capDate, int32_t(1702390128));
    capDate += "2:23:";
    const fs::path path =
        dir.write("attribute.exr", exr(8, 4, {"B", "G", "R"}, EXR_HALF, {}, capDate));
    try {
        scene::loadEnvironmentMap(path);
        ADD_FAILURE() << "a header without scanlines loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("attribute 'capDate' claims 1702390128 bytes"),
                  std::string::npos)
            << e.what();
    }
}

// environment_fuzz (2026-12-02): a 914-byte header with "chunkCount int"
// declaring 0 bytes. OpenEXR reads an int's 4 bytes whatever the size says,
// so its reading and the size check above walked the header differently,
// and a later string attribute claimed 850 MB (1.8 GB resident, past the
// fuzzer's 2 GB with its own). Fixed-size types must declare their size;
// the strings of a stringvector and a preview's pixels must fit in theirs,
// and a channel list must end where its size says.
TEST(EnvironmentFuzzRegression, AttributesOfTheWrongSizeForTheirTypeAreRefused) {
    TempDir dir;
    std::string chunkCount = std::string("chunkCount") + '\0' + "int" + '\0';
    put(chunkCount, int32_t(0));
    std::string strings = std::string("multiView") + '\0' + "stringvector" + '\0';
    put(strings, int32_t(8));
    put(strings, int32_t(1 << 30));  // one string of 1 GiB in 8 bytes
    put(strings, int32_t(0));
    std::string preview = std::string("preview") + '\0' + "preview" + '\0';
    put(preview, int32_t(8));
    put(preview, uint32_t(1 << 16));  // 2^32 pixels in none
    put(preview, uint32_t(1 << 16));
    // environment_fuzz (2026-12-02): OpenImageIO aborts on a channel of pixel type 3.
    std::string channels = std::string("channels") + '\0' + "chlist" + '\0';
    std::string list = std::string("R") + '\0';
    put(list, int32_t(3));
    put(list, int32_t(0));
    put(list, int32_t(1));
    put(list, int32_t(1));
    list += '\0';
    put(channels, int32_t(list.size()));
    channels += list;
    // environment_fuzz (2026-12-06): a channel list that ends before its
    // declared size; OpenEXR reads its last bytes as the next attribute.
    std::string shortList = std::string("channels") + '\0' + "chlist" + '\0';
    std::string oneChannel = std::string("R") + '\0';
    put(oneChannel, int32_t(1));
    put(oneChannel, int32_t(0));
    put(oneChannel, int32_t(1));
    put(oneChannel, int32_t(1));
    oneChannel += '\0';
    put(shortList, int32_t(oneChannel.size() + 4));
    shortList += oneChannel;
    put(shortList, int32_t(0));
    const std::pair<std::string, std::string> cases[] = {
        {channels, "channel 'R' has pixel type 3"},
        {shortList, "channel list 'channels' ends 4 bytes before its size says"},
        {chunkCount, "attribute 'chunkCount' of type int is 0 bytes, not 4"},
        {strings, "a string of attribute 'multiView' runs past its end"},
        {preview, "preview 'preview' claims 65536x65536 pixels in 8 bytes"},
    };
    for (const auto& [attributes, says] : cases) {
        const fs::path path =
            dir.write("attribute.exr", exr(8, 4, {"B", "G", "R"}, EXR_HALF, {}, attributes));
        try {
            scene::loadEnvironmentMap(path);
            ADD_FAILURE() << "a header without scanlines loaded";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
        }
    }
}

// The same fix must keep reading the right three: with channels A, B, G, R
// and Z, OpenImageIO presents R, G, B first, and those are the radiance.
TEST(EnvironmentFuzzRegression, ExtraChannelsAreIgnored) {
    TempDir dir;
    // Per scanline, per channel in file order A B G R Z, two texels each.
    const std::vector<float> pixels = {0.5f, 0.5f, 3.0f, 6.0f, 2.0f, 5.0f, 1.0f, 4.0f, 9.0f, 9.0f};
    const fs::path path =
        dir.write("rgbaz.exr", exr(2, 1, {"A", "B", "G", "R", "Z"}, EXR_FLOAT, pixels));
    const image::Image map = scene::loadEnvironmentMap(path);
    ASSERT_EQ(map.width, 2u);
    ASSERT_EQ(map.height, 1u);
    EXPECT_EQ(map.at(0, 0), glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(map.at(1, 0), glm::vec3(4.0f, 5.0f, 6.0f));
}

// ---------------------------------------------------------------------------
// Numbers finite in the file but not as the scene's 32-bit floats
// ---------------------------------------------------------------------------

// The InputError of loading `bytes` as `name`; fails the test if it loads.
std::string refusal(const TempDir& dir, const std::string& name, const std::string& bytes) {
    const fs::path path = dir.write(name, bytes);
    try {
        scene::loadScene(path);
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
        return message;
    }
    ADD_FAILURE() << name << " loaded";
    return {};
}

std::string dae(const std::string& matrix) {
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <library_lights><light id="sun"><technique_common><directional><color>1 1 1</color>
  </directional></technique_common></light></library_lights>
  <library_geometries><geometry id="tri"><mesh>
    <source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3"/></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s">
    <node id="t"><instance_geometry url="#tri"/></node>
    <node id="light"><matrix>)" +
           matrix + R"(</matrix><instance_light url="#sun"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)";
}

// collada_fuzz (tools/fuzz-smoke 300): a node <matrix> holding a 90-digit
// number (5.6e88: finite as a double, not as a float) gave a directional
// light a non-finite direction, and `render` drew the scene with 122 NaN/Inf
// samples dropped and exit code 0. Reduced here to the light, its matrix and
// a triangle. A number beyond a float's range is bad input now, and so is a
// world transform whose product leaves it (1e20 x 1e20).
TEST(ColladaFuzzRegression, NumbersBeyondAFloatAreBadInput) {
    const TempDir dir;
    const std::string huge(90, '5');
    EXPECT_NE(refusal(dir, "huge.dae",
                      dae("0.7 0.5 0.5 1 -0.7 0.5 0.5 1 0 -0.7 0" + huge + ".7 1.5 0 0 0 1"))
                  .find("is beyond the range of a 32-bit float"),
              std::string::npos);
    const std::string product = dae("1e20 0 0 0 0 1e20 0 0 0 0 1e20 0 0 0 0 1");
    const std::string nested =
        std::string(product).replace(product.find("<instance_light url=\"#sun\"/>"),
                                     std::string("<instance_light url=\"#sun\"/>").size(),
                                     "<node id=\"inner\"><matrix>1e20 0 0 0 0 1e20 0 0 0 0 1e20 "
                                     "0 0 0 0 1</matrix><instance_light url=\"#sun\"/></node>");
    EXPECT_NE(refusal(dir, "nested.dae", nested).find("not finite as 32-bit floats"),
              std::string::npos);
}

// The finding itself, where the shared folder has it.
TEST(ColladaFuzzRegression, TheOverflowingMatrixFindingIsBadInput) {
    const fs::path finding =
        test::scenesDir().parent_path() / "fuzz-findings" / "collada_overflowing_matrix.dae";
    if (!fs::exists(finding)) GTEST_SKIP() << "no " << finding.string();
    try {
        scene::loadScene(finding);
        ADD_FAILURE() << "loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("beyond the range of a 32-bit float"),
                  std::string::npos)
            << e.what();
    }
}

// The same in glTF, in any field: a node matrix, a material factor, a light's
// intensity, named by JSON pointer; and a product of node scales.
TEST(GltfFuzzRegression, NumbersBeyondAFloatAreBadInput) {
    const TempDir dir;
    const std::string head = R"({"asset": {"version": "2.0"}, )";
    EXPECT_NE(refusal(dir, "matrix.gltf",
                      head + R"("nodes": [{"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5e88,1]}]})")
                  .find(": /nodes/0/matrix/14 is 5e+88, beyond the range of a 32-bit float"),
              std::string::npos);
    EXPECT_NE(
        refusal(dir, "factor.gltf", head + R"("materials": [{"emissiveFactor": [1, 1, -3.5e38]}]})")
            .find("/materials/0/emissiveFactor/2 is -3.5e+38"),
        std::string::npos);
    EXPECT_NE(refusal(dir, "scales.gltf",
                      head + R"("scene": 0, "scenes": [{"nodes": [0]}], "nodes": [)"
                             R"({"scale": [1e20, 1e20, 1e20], "children": [1]},)"
                             R"({"scale": [1e20, 1e20, 1e20]}]})")
                  .find("node 1: its world transform is not finite as 32-bit floats"),
              std::string::npos);
}

// gltf_fuzz (make fuzz, an hour): the bundled normal-maps GLB with its
// camera node's key misspelled and a position moved 7e22 m away. The default
// camera framed the box in floats, whose diagonal squared past a float's
// range: an infinite camera. It is framed in double now; bounds that leave
// even that far past the range refuse the file.
TEST(GltfFuzzRegression, FarGeometryGetsAFiniteDefaultCamera) {
    const TempDir dir;
    auto triangle = [&](const std::string& far) {
        return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
            "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0, 0, )" +
               far + R"(]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 3,
                           "min": [0, 0, 0], "max": [1, 1, 0]}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
    };
    const scene::Scene s = scene::loadScene(dir.write("far.gltf", triangle("7e22")));
    for (const glm::vec3& v : {s.camera.position, s.camera.target})
        EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
    EXPECT_GT(s.camera.position.z, 7e22f);
    EXPECT_NE(refusal(dir, "farther.gltf", triangle("3e38")).find("too large to frame one"),
              std::string::npos);
}

}  // namespace
