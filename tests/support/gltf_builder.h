// Writes small glTF files for the importer's tests: a document and its one
// binary buffer, as .gltf (embedded, external or absent buffer) or .glb; and
// loads them with stderr captured.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#include <nlohmann/json.hpp>
#pragma GCC diagnostic pop

#include "input_error.h"
#include "scene/gltf_loader.h"
#include "support/base64.h"

// That `haystack` (a string) holds `needle`, showing it where not.
#define EXPECT_CONTAINS(haystack, needle)                                    \
    do {                                                                     \
        const std::string text_ = (haystack);                                \
        EXPECT_NE(text_.find(needle), std::string::npos) << "in: " << text_; \
    } while (0)

namespace vkpath::test {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// glTF componentType values.
inline constexpr int U8 = 5121, U16 = 5123, U32 = 5125, F32 = 5126;

inline void writeBytes(const fs::path& path, const void* data, size_t size) {
    std::ofstream out(path, std::ios::binary);
    out.write(static_cast<const char*>(data), std::streamsize(size));
}

inline void writeText(const fs::path& path, const std::string& text) {
    writeBytes(path, text.data(), text.size());
}

// Builds a glTF document and its one binary buffer.
class GltfBuilder {
  public:
    Json doc;
    std::vector<uint8_t> bin;

    GltfBuilder() {
        doc["asset"] = {{"version", "2.0"}};
        doc["scene"] = 0;
        doc["scenes"] = Json::array({Json{{"nodes", Json::array()}}});
        doc["nodes"] = Json::array();
        doc["meshes"] = Json::array();
        doc["accessors"] = Json::array();
        doc["bufferViews"] = Json::array();
    }

    // glTF arrays must not be empty: drop those the test left empty.
    Json trimmed() const {
        Json d = doc;
        for (const char* key : {"nodes", "meshes", "accessors", "bufferViews"})
            if (d[key].empty()) d.erase(key);
        return d;
    }

    int view(const void* data, size_t bytes, size_t stride = 0) {
        while (bin.size() % 4) bin.push_back(0);
        Json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (stride) v["byteStride"] = stride;
        const auto* p = static_cast<const uint8_t*>(data);
        bin.insert(bin.end(), p, p + bytes);
        doc["bufferViews"].push_back(v);
        return int(doc["bufferViews"].size() - 1);
    }

    int accessor(int bufferView, int componentType, const char* type, size_t count,
                 size_t offset = 0) {
        Json a = {{"bufferView", bufferView},
                  {"componentType", componentType},
                  {"type", type},
                  {"count", count}};
        if (offset) a["byteOffset"] = offset;
        doc["accessors"].push_back(a);
        return int(doc["accessors"].size() - 1);
    }

    int vec3s(const std::vector<glm::vec3>& values) {
        return accessor(view(values.data(), values.size() * sizeof(glm::vec3)), F32, "VEC3",
                        values.size());
    }

    int indices(const std::vector<uint32_t>& values, int componentType) {
        std::vector<uint8_t> bytes;
        const size_t size = componentType == U8 ? 1 : componentType == U16 ? 2 : 4;
        for (uint32_t v : values)
            for (size_t b = 0; b < size; ++b) bytes.push_back(uint8_t(v >> (8 * b)));
        return accessor(view(bytes.data(), bytes.size()), componentType, "SCALAR", values.size());
    }

    int mesh(int positions, int indexAccessor = -1, int normals = -1, int material = -1,
             int mode = -1) {
        Json primitive = {{"attributes", {{"POSITION", positions}}}};
        if (normals >= 0) primitive["attributes"]["NORMAL"] = normals;
        if (indexAccessor >= 0) primitive["indices"] = indexAccessor;
        if (material >= 0) primitive["material"] = material;
        if (mode >= 0) primitive["mode"] = mode;
        doc["meshes"].push_back({{"primitives", Json::array({primitive})}});
        return int(doc["meshes"].size() - 1);
    }

    int node(Json n, bool root = true) {
        doc["nodes"].push_back(std::move(n));
        const int index = int(doc["nodes"].size() - 1);
        if (root) doc["scenes"][0]["nodes"].push_back(index);
        return index;
    }

    int material(Json m) {
        doc["materials"].push_back(std::move(m));
        return int(doc["materials"].size() - 1);
    }

    // A triangle in the z = 0 plane facing +Z (counter-clockwise from +Z),
    // with a +Z vertex normal; returns the mesh index.
    int triangle(int material = -1) {
        const int p = vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        const int n = vec3s({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
        return mesh(p, -1, n, material);
    }

    // A unit UV sphere of 4 r (r - 1) triangles with normals (and texture
    // coordinates), as one indexed mesh of `material` (-1: none); returns the
    // mesh index.
    int uvSphere(int rings, bool texcoords, int material = -1) {
        std::vector<glm::vec3> positions;
        std::vector<glm::vec2> uvs;
        const int segments = 2 * rings;
        for (int r = 0; r <= rings; ++r)
            for (int s = 0; s <= segments; ++s) {
                const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
                positions.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta),
                                       std::sin(theta) * std::sin(phi));
                uvs.emplace_back(float(s) / float(segments), float(r) / float(rings));
            }
        std::vector<uint32_t> corners;
        for (int r = 0; r < rings; ++r)
            for (int s = 0; s < segments; ++s) {
                const uint32_t a = uint32_t(r * (segments + 1) + s), c = a + uint32_t(segments + 1);
                if (r > 0) corners.insert(corners.end(), {a, a + 1, c});
                if (r < rings - 1) corners.insert(corners.end(), {a + 1, c + 1, c});
            }
        const int p = vec3s(positions);
        const int n = vec3s(positions);  // a unit sphere's normals are its positions
        const int m = mesh(p, indices(corners, U32), n, material);
        if (texcoords)
            doc["meshes"][size_t(m)]["primitives"][0]["attributes"]["TEXCOORD_0"] =
                accessor(view(uvs.data(), uvs.size() * sizeof(glm::vec2)), F32, "VEC2", uvs.size());
        return m;
    }

    enum class Buffer { Embedded, External, None };

    // A perspective camera at +Z looking at the origin, so a scene needs no default camera.
    void camera() {
        doc["cameras"].push_back(
            {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}});
        node({{"camera", doc["cameras"].size() - 1}, {"translation", {0, 0, 10}}});
    }

    fs::path writeGltf(const fs::path& path, Buffer mode = Buffer::Embedded) const {
        Json d = trimmed();
        if (mode == Buffer::Embedded && !bin.empty())
            d["buffers"] =
                Json::array({{{"byteLength", bin.size()},
                              {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        if (mode == Buffer::External) {
            const fs::path binPath = fs::path(path).replace_extension(".bin");
            writeBytes(binPath, bin.data(), bin.size());
            d["buffers"] =
                Json::array({{{"byteLength", bin.size()}, {"uri", binPath.filename().string()}}});
        }
        if (mode == Buffer::None && !bin.empty())
            d["buffers"] = Json::array({{{"byteLength", bin.size()}}});
        writeText(path, d.dump(1));
        return path;
    }

    // GLB: 12-byte header, JSON chunk (space-padded), BIN chunk (zero-padded).
    std::vector<uint8_t> glb() const {
        Json d = trimmed();
        d["buffers"] = Json::array({{{"byteLength", bin.size()}}});
        std::string json = d.dump();
        while (json.size() % 4) json += ' ';
        std::vector<uint8_t> data = bin;
        while (data.size() % 4) data.push_back(0);
        std::vector<uint8_t> out;
        auto u32 = [&](uint32_t v) {
            for (int b = 0; b < 4; ++b) out.push_back(uint8_t(v >> (8 * b)));
        };
        u32(0x46546C67);
        u32(2);
        u32(uint32_t(12 + 8 + json.size() + 8 + data.size()));
        u32(uint32_t(json.size()));
        u32(0x4E4F534A);
        out.insert(out.end(), json.begin(), json.end());
        u32(uint32_t(data.size()));
        u32(0x004E4942);
        out.insert(out.end(), data.begin(), data.end());
        return out;
    }

    fs::path writeGlb(const fs::path& path) const {
        const auto bytes = glb();
        writeBytes(path, bytes.data(), bytes.size());
        return path;
    }
};

struct Loaded {
    scene::Scene scene;
    std::string warnings;  // stderr during the load
};

inline Loaded load(const fs::path& path, const scene::LoadOptions& options = {}) {
    testing::internal::CaptureStderr();
    try {
        scene::Scene s = scene::loadGltf(path, options);
        return {std::move(s), testing::internal::GetCapturedStderr()};
    } catch (...) {
        testing::internal::GetCapturedStderr();
        throw;
    }
}

// The InputError message of loading `path`; fails the test if it loads.
inline std::string loadError(const fs::path& path, const scene::LoadOptions& options = {}) {
    testing::internal::CaptureStderr();
    try {
        scene::loadGltf(path, options);
    } catch (const InputError& e) {
        testing::internal::GetCapturedStderr();
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
        EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u)
            << "does not name the file: " << message;
        return message;
    }
    testing::internal::GetCapturedStderr();
    ADD_FAILURE() << path << " loaded without an error";
    return {};
}

}  // namespace vkpath::test
