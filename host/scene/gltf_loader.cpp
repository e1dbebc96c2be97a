// glTF 2.0 import. The phases, in order:
//   1. read the file and, for .glb, check the container (lengths, chunk
//      types, alignment) ourselves: tinygltf's GLB checks have had gaps;
//   2. parse the JSON once to check every buffer/image URI before tinygltf
//      touches the file system: no scheme, not absolute, no "..", present,
//      and not a symbolic link out of the folder. tinygltf then reads files
//      only through file-system callbacks that enforce the same rule;
//   3. tinygltf builds its model (images are not decoded: textures are not
//      modelled);
//   4. vkpath walks the node hierarchy and converts: every accessor is range-
//      checked against its bufferView and buffer before a byte is read.
#include "scene/gltf_loader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <optional>
#include <set>
#include <span>
#include <string_view>

#include "input_error.h"
#include "scene/environment.h"

// Third-party headers: their warnings are not ours (-Werror).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <nlohmann/json.hpp>
// The shared library libtinygltf carries the implementation (with stb_image
// and nlohmann/json); the header alone only declares it, so no
// TINYGLTF_IMPLEMENTATION and no STB/JSON defines here.
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace vkpath::scene {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr uint64_t MAX_FILE_BYTES = uint64_t(1) << 30;  // the scene file and each external file
constexpr size_t MAX_ACCESSOR_COUNT = size_t(1) << 25;  // elements per accessor
// An accessor without a bufferView is all zeros (or sparse substitutions):
// a few bytes of JSON must not allocate gigabytes.
constexpr size_t MAX_ZERO_ACCESSOR_COUNT = size_t(1) << 20;
constexpr uint32_t GLB_MAGIC = 0x46546C67;       // "glTF"
constexpr uint32_t GLB_CHUNK_JSON = 0x4E4F534A;  // "JSON"
constexpr uint32_t GLB_CHUNK_BIN = 0x004E4942;   // "BIN\0"
constexpr double DEFAULT_CAMERA_FOV_DEGREES = 40.0;

// Extensions whose meaning vkpath models. Any other one is reported when used
// and refused when required.
const std::set<std::string> SUPPORTED_EXTENSIONS = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_ior",
    "KHR_materials_transmission", "VKPATH_environment", "VKPATH_sphere"};

// ---------------------------------------------------------------------------
// Warnings: one line per kind, with a count and the first example.
// ---------------------------------------------------------------------------

class Warnings {
  public:
    explicit Warnings(std::string file) : m_file(std::move(file)) {}

    // Counts `count` occurrences of the kind named by `message`; `unit` names
    // what is counted (empty: print no count), `example` the first one seen.
    void add(const std::string& message, const std::string& unit = {},
             const std::string& example = {}, size_t count = 1) {
        for (Entry& e : m_entries)
            if (e.message == message) {
                e.count += count;
                return;
            }
        m_entries.push_back({message, unit, example, count});
    }

    void print() const {
        for (const Entry& e : m_entries) {
            std::string line = fmt::format("vkpath: warning: {}: {}", m_file, e.message);
            if (!e.unit.empty())
                line += fmt::format(" ({} {}{}{})", e.count, e.unit, e.count == 1 ? "" : "s",
                                    e.example.empty() ? "" : ", first: " + e.example);
            std::fprintf(stderr, "%s\n", line.c_str());
        }
    }

  private:
    struct Entry {
        std::string message, unit, example;
        size_t count = 0;
    };
    std::string m_file;
    std::vector<Entry> m_entries;  // in order of first occurrence
};

// ---------------------------------------------------------------------------
// Phase 1: the file and the GLB container
// ---------------------------------------------------------------------------

std::vector<uint8_t> readWholeFile(const fs::path& path, uint64_t maxBytes, std::string& error) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) {
        error = "no such file";
        return {};
    }
    if (!fs::is_regular_file(status)) {
        error = "not a regular file";
        return {};
    }
    const uintmax_t size = fs::file_size(path, ec);
    if (ec) {
        error = "cannot read: " + ec.message();
        return {};
    }
    if (size > maxBytes) {
        error = fmt::format("{} bytes exceed the limit of {}", size, maxBytes);
        return {};
    }
    std::vector<uint8_t> bytes(size);
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size))) {
        error = "cannot read";
        return {};
    }
    return bytes;
}

uint32_t readU32(std::span<const uint8_t> bytes, size_t offset) {
    return uint32_t(bytes[offset]) | uint32_t(bytes[offset + 1]) << 8 |
           uint32_t(bytes[offset + 2]) << 16 | uint32_t(bytes[offset + 3]) << 24;
}

struct GlbChunks {
    std::span<const uint8_t> json;
    bool hasBin = false;
};

// The GLB layout (glTF 2.0 spec, section 4.4): a 12-byte header (magic,
// version 2, total length), a JSON chunk, then optionally a BIN chunk; each
// chunk is an 8-byte header (length, type) and 4-byte-aligned data.
GlbChunks parseGlb(std::span<const uint8_t> bytes, const std::string& file) {
    auto fail = [&](const std::string& what) {
        throw InputError(fmt::format("{}: {}", file, what));
    };
    const uint64_t size = bytes.size();
    if (size < 12) fail(fmt::format("truncated GLB: {} bytes, the header alone has 12", size));
    if (readU32(bytes, 4) != 2)
        fail(fmt::format("GLB version {} is not supported (only 2)", readU32(bytes, 4)));
    const uint64_t length = readU32(bytes, 8);
    if (length > size)
        fail(fmt::format("truncated GLB: the header says {} bytes, the file has {}", length, size));
    if (length < size) fail(fmt::format("GLB header says {} bytes, the file has {}", length, size));
    if (length < 20) fail("truncated GLB: no JSON chunk");
    const uint64_t jsonLength = readU32(bytes, 12);
    if (readU32(bytes, 16) != GLB_CHUNK_JSON) fail("the first GLB chunk is not JSON");
    if (jsonLength == 0 || jsonLength > length - 20)
        fail(
            fmt::format("truncated GLB: the JSON chunk of {} bytes overruns the file", jsonLength));
    if (jsonLength % 4 != 0)
        fail(fmt::format("GLB JSON chunk length {} is not a multiple of 4", jsonLength));
    GlbChunks chunks;
    chunks.json = bytes.subspan(20, jsonLength);
    const uint64_t binHeader = 20 + jsonLength;
    if (binHeader < length) {
        if (length - binHeader < 8)
            fail("truncated GLB: incomplete chunk header after the JSON chunk");
        const uint64_t binLength = readU32(bytes, binHeader);
        if (readU32(bytes, binHeader + 4) != GLB_CHUNK_BIN) fail("the second GLB chunk is not BIN");
        if (binLength > length - binHeader - 8)
            fail(fmt::format("truncated GLB: the BIN chunk of {} bytes overruns the file",
                             binLength));
        if (binLength == 0 || binLength % 4 != 0)
            fail(fmt::format("GLB BIN chunk length {} is not a positive multiple of 4", binLength));
        chunks.hasBin = true;
    }
    return chunks;
}

// ---------------------------------------------------------------------------
// Phase 2: URIs
// ---------------------------------------------------------------------------

// Decoded as tinygltf decodes before it opens a file (dlib::urldecode: %XX,
// and '+' as a space), so the file checked is the file tinygltf would read.
std::string decodeUri(const std::string& uri) {
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return 0;
    };
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && uri.size() > i + 2) {
            out += char(hex(uri[i + 1]) << 4 | hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

bool isInside(const fs::path& canonicalPath, const fs::path& canonicalFolder) {
    auto p = canonicalPath.begin();
    for (auto f = canonicalFolder.begin(); f != canonicalFolder.end(); ++f, ++p) {
        if (f->empty()) continue;  // a trailing separator
        if (p == canonicalPath.end() || *p != *f) return false;
    }
    return true;
}

// Why `uri` (a file URI) may not be read from `folder`, or "" when it may.
std::string uriProblem(const std::string& uri, const fs::path& folder) {
    const std::string path = decodeUri(uri);
    if (path.empty()) return "is empty";
    for (char c : path)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "contains control characters";
    const size_t colon = path.find(':'), slash = path.find_first_of("/\\");
    if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
        return "has a scheme or drive; only relative file paths and data: URIs are allowed";
    if (path[0] == '/' || path[0] == '\\' || fs::path(path).is_absolute())
        return "is an absolute path";
    size_t start = 0;
    while (start <= path.size()) {
        const size_t end = std::min(path.find_first_of("/\\", start), path.size());
        if (path.compare(start, end - start, "..") == 0 && end - start == 2)
            return "leaves the scene's folder";
        start = end + 1;
    }
    std::error_code ec;
    const fs::path full = folder / path;
    if (!fs::exists(full, ec)) return "names a file that does not exist";
    if (!fs::is_regular_file(full, ec)) return "does not name a regular file";
    const fs::path canonicalFile = fs::canonical(full, ec);
    const fs::path canonicalFolder = fs::canonical(folder, ec);
    if (ec || !isInside(canonicalFile, canonicalFolder))
        return "leaves the scene's folder through a link";
    return {};
}

// Every external file a glTF names, checked before tinygltf opens any.
void checkUris(const Json& root, const fs::path& folder, bool binary, bool hasBin,
               const std::string& file) {
    for (const char* key : {"buffers", "images"}) {
        const auto list = root.find(key);
        if (list == root.end()) continue;
        if (!list->is_array()) throw InputError(fmt::format("{}: '{}' is not an array", file, key));
        const std::string what = key[0] == 'b' ? "buffer" : "image";
        for (size_t i = 0; i < list->size(); ++i) {
            const Json& entry = (*list)[i];
            if (!entry.is_object())
                throw InputError(fmt::format("{}: {} {} is not an object", file, what, i));
            const auto uri = entry.find("uri");
            if (uri == entry.end()) {
                if (what == "buffer" && !(binary && i == 0 && hasBin))
                    throw InputError(fmt::format("{}: buffer {} has no uri{}", file, i,
                                                 binary ? " and is not the GLB's BIN chunk" : ""));
                continue;
            }
            if (!uri->is_string())
                throw InputError(fmt::format("{}: {} {}: uri is not a string", file, what, i));
            const std::string& text = uri->get_ref<const std::string&>();
            if (text.rfind("data:", 0) == 0) {
                // The buffer data URIs tinygltf decodes; it would take any other as a file name.
                if (what == "buffer" &&
                    text.rfind("data:application/octet-stream;base64,", 0) != 0 &&
                    text.rfind("data:application/gltf-buffer;base64,", 0) != 0)
                    throw InputError(fmt::format(
                        "{}: buffer {}: data URI is not base64 application/octet-stream "
                        "or application/gltf-buffer",
                        file, i));
                continue;  // images are not decoded
            }
            const std::string problem = uriProblem(text, folder);
            if (!problem.empty())
                throw InputError(
                    fmt::format("{}: {} {}: uri '{}' {}", file, what, i, text, problem));
        }
    }
}

// tinygltf's file-system callbacks: reads only regular files inside the
// scene's folder (symbolic links resolved), never writes.
struct FolderGuard {
    fs::path canonicalFolder;
    std::vector<fs::path> read;  // what guardedReadWholeFile read, in order

    bool allows(const std::string& name) const {
        std::error_code ec;
        const fs::path path = fs::canonical(name, ec);
        return !ec && fs::is_regular_file(path, ec) && isInside(path, canonicalFolder);
    }
};

bool guardedFileExists(const std::string& name, void* user) {
    return static_cast<const FolderGuard*>(user)->allows(name);
}

std::string unexpandedPath(const std::string& path, void*) {
    return path;
}

bool guardedReadWholeFile(std::vector<unsigned char>* out, std::string* err,
                          const std::string& name, void* user) {
    if (!static_cast<const FolderGuard*>(user)->allows(name)) {
        if (err) *err += name + ": outside the scene's folder\n";
        return false;
    }
    std::string error;
    *out = readWholeFile(name, MAX_FILE_BYTES, error);
    if (!error.empty() && err) *err += name + ": " + error + "\n";
    if (error.empty()) static_cast<FolderGuard*>(user)->read.push_back(name);
    return error.empty();
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "vkpath does not write glTF files\n";
    return false;
}

// Textures are not modelled, so images are kept undecoded.
bool keepImageUndecoded(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                        const unsigned char*, int, void*) {
    return true;
}

// tinygltf's messages end lines with '\n'; ours are one line.
std::string oneLine(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    for (size_t i; (i = text.find('\n')) != std::string::npos;) text.replace(i, 1, "; ");
    return text;
}

// ---------------------------------------------------------------------------
// Phase 4: conversion
// ---------------------------------------------------------------------------

const char* modeName(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS:
            return "POINTS";
        case TINYGLTF_MODE_LINE:
            return "LINES";
        case TINYGLTF_MODE_LINE_LOOP:
            return "LINE_LOOP";
        case TINYGLTF_MODE_LINE_STRIP:
            return "LINE_STRIP";
        case TINYGLTF_MODE_TRIANGLES:
            return "TRIANGLES";
        case TINYGLTF_MODE_TRIANGLE_STRIP:
            return "TRIANGLE_STRIP";
        case TINYGLTF_MODE_TRIANGLE_FAN:
            return "TRIANGLE_FAN";
        default:
            return "unknown";
    }
}

// The vertex indices of `mode`'s primitives (in drawing order) as a
// triangle list: glTF 2.0, 3.7.2.1 "Topology Types". A strip's triangle i is
// (v_i, v_{i+1+i%2}, v_{i+2-i%2}), which keeps every second triangle's
// winding counter-clockwise; a fan's is (v_{i+1}, v_{i+2}, v_0). Strips and
// fans of fewer than three vertices draw nothing.
std::vector<uint32_t> triangleList(int mode, std::vector<uint32_t> vertices) {
    if (mode == TINYGLTF_MODE_TRIANGLES) return vertices;
    std::vector<uint32_t> list;
    for (size_t i = 0; i + 2 < vertices.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
            list.insert(list.end(), {vertices[i], vertices[i + 1 + i % 2], vertices[i + 2 - i % 2]});
        else
            list.insert(list.end(), {vertices[i + 1], vertices[i + 2], vertices[0]});
    }
    return list;
}

const char* typeName(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
        default:
            return "unknown";
    }
}

// Bytes per component; 0 for a type glTF 2.0 does not allow.
size_t componentSize(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

size_t componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        case TINYGLTF_TYPE_MAT2:
            return 4;
        case TINYGLTF_TYPE_MAT3:
            return 9;
        case TINYGLTF_TYPE_MAT4:
            return 16;
        default:
            return 0;
    }
}

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

struct CameraCandidate {
    int node;
    int camera;
    glm::dmat4 world;
};

class Importer {
  public:
    Importer(std::string file, fs::path folder, const tinygltf::Model& model, const LoadOptions& options)
        : m_file(std::move(file)), m_folder(std::move(folder)), m_model(model), m_options(options),
          m_warnings(m_file) {}

    Scene run() {
        checkExtensions();
        for (size_t i = 0; i < m_model.materials.size(); ++i)
            m_scene.materials.push_back(mapMaterial(m_model.materials[i], i));
        if (!m_model.animations.empty())
            m_warnings.add("animations are ignored: the scene is loaded at rest", "animation",
                           m_model.animations[0].name);

        for (const Visit& visit : traverse()) visitNode(visit.node, visit.world);

        if (m_scene.meshes.empty() && m_scene.spheres.empty())
            fail("no geometry: the scene has no triangles and no spheres");
        chooseCamera();
        readEnvironment();
        m_warnings.print();
        return std::move(m_scene);
    }

  private:
    struct Visit {
        int node;
        glm::dmat4 world;
    };

    template <typename... Args>
    [[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) const {
        throw InputError(
            fmt::format("{}: {}", m_file, fmt::format(format, std::forward<Args>(args)...)));
    }

    std::string nodeName(int index) const {
        const std::string& name = m_model.nodes[size_t(index)].name;
        return name.empty() ? fmt::format("node {}", index) : fmt::format("node '{}'", name);
    }

    // ---- extensions --------------------------------------------------------

    void checkExtensions() {
        std::set<std::string> used(m_model.extensionsUsed.begin(), m_model.extensionsUsed.end());
        auto collect = [&](const tinygltf::ExtensionMap& map) {
            for (const auto& entry : map) used.insert(entry.first);
        };
        collect(m_model.extensions);
        for (const auto& m : m_model.materials) {
            collect(m.extensions);
            collect(m.pbrMetallicRoughness.extensions);
        }
        for (const auto& n : m_model.nodes) collect(n.extensions);
        for (const auto& m : m_model.meshes)
            for (const auto& p : m.primitives) collect(p.extensions);
        for (const auto& c : m_model.cameras) collect(c.extensions);
        for (const auto& t : m_model.textures) collect(t.extensions);
        for (const std::string& name : used)
            if (!SUPPORTED_EXTENSIONS.contains(name))
                m_warnings.add(fmt::format("extension '{}' is not supported and is ignored", name));
    }

    // ---- the environment ------------------------------------------------------

    // VKPATH_environment (docs/SCENES.md), on the glTF root: the light from
    // infinitely far away, so that a scene file carries its sky. Either an
    // equirectangular map `uri` (relative to the scene's folder, inside it) or
    // a constant `color`, times `strength`, turned `rotation` degrees about +Y.
    void readEnvironment() {
        const auto it = m_model.extensions.find("VKPATH_environment");
        if (it == m_model.extensions.end()) return;
        const tinygltf::Value& ext = it->second;
        const std::string what = "VKPATH_environment";
        if (!ext.IsObject()) fail("{} is not an object", what);
        auto number = [&](const char* key, double fallback) {
            if (!ext.Has(key)) return fallback;
            const tinygltf::Value& value = ext.Get(key);
            if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
                fail("{}: '{}' is not a finite number", what, key);
            return value.GetNumberAsDouble();
        };
        Environment env;
        env.strength = float(number("strength", 1.0));
        if (!(env.strength >= 0.0f)) fail("{}: strength {} is negative", what, env.strength);
        env.rotationDegrees = float(number("rotation", 0.0));
        if (ext.Has("uri") == ext.Has("color")) fail("{} needs exactly one of 'uri' and 'color'", what);
        if (ext.Has("uri")) {
            const tinygltf::Value& uri = ext.Get("uri");
            if (!uri.IsString()) fail("{}: uri is not a string", what);
            const std::string problem = uriProblem(uri.Get<std::string>(), m_folder);
            if (!problem.empty()) fail("{}: uri '{}' {}", what, uri.Get<std::string>(), problem);
            const fs::path mapPath = m_folder / decodeUri(uri.Get<std::string>());
            env.map = loadEnvironmentMap(mapPath);
            m_scene.referencedFiles.push_back(mapPath);
        } else {
            const tinygltf::Value& color = ext.Get("color");
            if (!color.IsArray() || color.ArrayLen() != 3) fail("{}: color is not an array of 3 numbers", what);
            for (int c = 0; c < 3; ++c) {
                const tinygltf::Value& v = color.Get(c);
                if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()) || v.GetNumberAsDouble() < 0.0)
                    fail("{}: color is not 3 finite numbers >= 0", what);
                env.color[c] = float(v.GetNumberAsDouble());
            }
        }
        m_scene.environment = std::move(env);
    }

    // ---- materials -----------------------------------------------------------

    // A factor in [0, 1]: NaN is an error, anything outside is clamped.
    double factor(double value, const char* what, const std::string& material) {
        if (!std::isfinite(value)) fail("material '{}': {} is not a finite number", material, what);
        if (value < 0.0 || value > 1.0) {
            m_warnings.add("material factors outside [0, 1] are clamped", "material", material);
            value = std::clamp(value, 0.0, 1.0);
        }
        return value;
    }

    // extension.key as a number, `fallback` when the extension or key is absent.
    double extensionNumber(const tinygltf::ExtensionMap& extensions, const char* extension,
                           const char* key, double fallback, const std::string& material) {
        const auto it = extensions.find(extension);
        if (it == extensions.end()) return fallback;
        if (!it->second.IsObject()) fail("material '{}': {} is not an object", material, extension);
        if (!it->second.Has(key)) return fallback;
        const tinygltf::Value& value = it->second.Get(key);
        if (!value.IsNumber())
            fail("material '{}': {}.{} is not a number", material, extension, key);
        return value.GetNumberAsDouble();
    }

    static bool usesTexture(const tinygltf::Material& m) {
        const auto& pbr = m.pbrMetallicRoughness;
        if (pbr.baseColorTexture.index >= 0 || pbr.metallicRoughnessTexture.index >= 0 ||
            m.normalTexture.index >= 0 || m.occlusionTexture.index >= 0 ||
            m.emissiveTexture.index >= 0)
            return true;
        for (const auto& [name, value] : m.extensions)
            for (const std::string& key : value.Keys())
                if (key.size() >= 7 && key.compare(key.size() - 7, 7, "Texture") == 0) return true;
        return false;
    }

    // The material mapping table of docs/SCENES.md.
    Material mapMaterial(const tinygltf::Material& m, size_t index) {
        Material out;
        out.name = m.name.empty() ? fmt::format("material {}", index) : m.name;
        const std::string& name = out.name;
        const auto& pbr = m.pbrMetallicRoughness;
        if (pbr.baseColorFactor.size() != 4)
            fail("material '{}': baseColorFactor needs 4 numbers", name);
        const glm::vec3 base(factor(pbr.baseColorFactor[0], "baseColorFactor", name),
                             factor(pbr.baseColorFactor[1], "baseColorFactor", name),
                             factor(pbr.baseColorFactor[2], "baseColorFactor", name));
        factor(pbr.baseColorFactor[3], "baseColorFactor", name);
        const double metallic = factor(pbr.metallicFactor, "metallicFactor", name);
        const double roughness = factor(pbr.roughnessFactor, "roughnessFactor", name);
        const double transmission =
            factor(extensionNumber(m.extensions, "KHR_materials_transmission", "transmissionFactor",
                                   0.0, name),
                   "transmissionFactor", name);
        const double ior = extensionNumber(m.extensions, "KHR_materials_ior", "ior", 1.5, name);
        if (!std::isfinite(ior) || ior < 1.0)
            fail("material '{}': ior {} is not a finite number >= 1", name, ior);

        if (usesTexture(m))
            m_warnings.add("textures are ignored; the constant factors are used", "material", name);
        if (m.alphaMode == "MASK" || m.alphaMode == "BLEND")
            m_warnings.add("alpha (alphaMode MASK or BLEND) is ignored; surfaces are opaque",
                           "material", name);
        if (metallic > 0.0 && metallic < 1.0)
            m_warnings.add(
                "partly metallic materials are approximated: metallicFactor >= 0.5 as metal, below "
                "as "
                "non-metal",
                "material", name);

        constexpr double SMOOTH =
            0.01;  // roughness at or below which a surface counts as perfectly smooth
        if (metallic >= 0.5) {
            out.reflectance = base;
            out.kind = roughness <= 0.5 ? MaterialKind::Mirror : MaterialKind::Diffuse;
            if (roughness > SMOOTH)
                m_warnings.add(
                    "rough metals are approximated: roughnessFactor <= 0.5 as a mirror, above as "
                    "diffuse",
                    "material", name);
        } else if (transmission >= 0.5) {
            out.kind = MaterialKind::Dielectric;
            out.reflectance = glm::vec3(1.0f);  // glTF's dielectric specular is untinted
            out.transmittance = base;  // KHR_materials_transmission: base colour tints what passes
            out.ior = float(ior);
            if (roughness > SMOOTH)
                m_warnings.add("rough transmission is approximated as smooth glass", "material",
                               name);
        } else {
            out.kind = MaterialKind::Diffuse;
            out.reflectance = base;
            if (roughness < 0.5 && transmission == 0.0)
                m_warnings.add(
                    "glossy non-metals (roughnessFactor < 0.5) are approximated as Lambertian: the "
                    "specular layer is dropped",
                    "material", name);
        }
        if (transmission > 0.0 && transmission < 1.0 && metallic < 0.5)
            m_warnings.add(
                "partial transmission is approximated: transmissionFactor >= 0.5 as glass, below "
                "as "
                "opaque",
                "material", name);

        glm::dvec3 emissive(0.0);
        if (!m.emissiveFactor.empty()) {
            if (m.emissiveFactor.size() != 3)
                fail("material '{}': emissiveFactor needs 3 numbers", name);
            for (int c = 0; c < 3; ++c)
                emissive[c] = factor(m.emissiveFactor[size_t(c)], "emissiveFactor", name);
        }
        const double strength = extensionNumber(m.extensions, "KHR_materials_emissive_strength",
                                                "emissiveStrength", 1.0, name);
        if (!std::isfinite(strength) || strength < 0.0)
            fail("material '{}': emissiveStrength {} is not a finite number >= 0", name, strength);
        out.emission = glm::vec3(emissive * strength);
        return out;
    }

    uint32_t defaultMaterial() {
        if (!m_defaultMaterial) {
            Material m;
            m.name = "default";  // grey Lambertian (albedo 0.8) for primitives without a material
            m_scene.materials.push_back(m);
            m_defaultMaterial = uint32_t(m_scene.materials.size() - 1);
        }
        return *m_defaultMaterial;
    }

    // ---- node hierarchy ------------------------------------------------------

    glm::dmat4 localMatrix(int index) const {
        const tinygltf::Node& node = m_model.nodes[size_t(index)];
        auto check = [&](const std::vector<double>& values, size_t size, const char* what) {
            if (!values.empty() && values.size() != size)
                fail("{}: {} needs {} numbers", nodeName(index), what, size);
            for (double v : values)
                if (!std::isfinite(v)) fail("{}: {} is not finite", nodeName(index), what);
        };
        check(node.matrix, 16, "matrix");
        check(node.translation, 3, "translation");
        check(node.rotation, 4, "rotation");
        check(node.scale, 3, "scale");
        if (!node.matrix.empty())
            return glm::make_mat4(node.matrix.data());  // column-major, as in glTF
        glm::dmat4 t(1.0), r(1.0), s(1.0);
        if (!node.translation.empty())
            t[3] = glm::dvec4(glm::make_vec3(node.translation.data()), 1.0);
        if (!node.rotation.empty()) {
            const auto& q = node.rotation;  // glTF order: x, y, z, w
            const glm::dquat quat(q[3], q[0], q[1], q[2]);
            if (!(glm::length(quat) > 0.0))
                fail("{}: rotation is a zero quaternion", nodeName(index));
            r = glm::mat4_cast(glm::normalize(quat));
        }
        if (!node.scale.empty()) {
            s[0][0] = node.scale[0];
            s[1][1] = node.scale[1];
            s[2][2] = node.scale[2];
        }
        return t * r * s;
    }

    // Depth-first, children in the order listed: "node order" for cameras.
    // glTF nodes form trees (at most one parent each) whose roots are the
    // scene's nodes; checking that first makes cycles unreachable.
    std::vector<Visit> traverse() {
        const size_t count = m_model.nodes.size();
        std::vector<int> parents(count, 0);
        for (size_t i = 0; i < count; ++i)
            for (int child : m_model.nodes[i].children) {
                if (child < 0 || size_t(child) >= count)
                    fail("{}: child {} does not exist", nodeName(int(i)), child);
                if (++parents[size_t(child)] > 1)
                    fail("{} has more than one parent", nodeName(child));
            }

        std::vector<int> roots;
        if (!m_model.scenes.empty()) {
            const int sceneIndex = m_model.defaultScene >= 0 ? m_model.defaultScene : 0;
            if (size_t(sceneIndex) >= m_model.scenes.size())
                fail("default scene {} does not exist", sceneIndex);
            if (m_model.scenes.size() > 1)
                m_warnings.add(fmt::format("the file has {} scenes; only scene {} is loaded",
                                           m_model.scenes.size(), sceneIndex));
            roots = m_model.scenes[size_t(sceneIndex)].nodes;
            std::vector<bool> seen(count, false);
            for (int root : roots) {
                if (root < 0 || size_t(root) >= count) fail("scene node {} does not exist", root);
                if (parents[size_t(root)] != 0)
                    fail("scene node {} is not a root: it has a parent", root);
                if (seen[size_t(root)]) fail("scene lists node {} twice", root);
                seen[size_t(root)] = true;
            }
        } else {
            for (size_t i = 0; i < count; ++i)
                if (parents[i] == 0) roots.push_back(int(i));
        }

        std::vector<Visit> order;
        std::vector<Visit> stack;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it)
            stack.push_back({*it, glm::dmat4(1.0)});
        while (!stack.empty()) {
            const Visit top = stack.back();
            stack.pop_back();
            const glm::dmat4 world = top.world * localMatrix(top.node);
            order.push_back({top.node, world});
            const auto& children = m_model.nodes[size_t(top.node)].children;
            for (auto it = children.rbegin(); it != children.rend(); ++it)
                stack.push_back({*it, world});
        }
        return order;
    }

    void visitNode(int index, const glm::dmat4& world) {
        const tinygltf::Node& node = m_model.nodes[size_t(index)];
        if (!node.matrix.empty() &&
            (!node.translation.empty() || !node.rotation.empty() || !node.scale.empty()))
            m_warnings.add("nodes with both a matrix and TRS use the matrix", "node",
                           nodeName(index));
        if (node.skin >= 0)
            m_warnings.add("skins are ignored: meshes are used as bound", "node", nodeName(index));
        if (node.mesh >= 0) addMesh(index, world);
        if (node.camera >= 0) {
            if (size_t(node.camera) >= m_model.cameras.size())
                fail("{}: camera {} does not exist", nodeName(index), node.camera);
            m_cameras.push_back({index, node.camera, world});
        }
        if (const auto it = node.extensions.find("KHR_lights_punctual");
            it != node.extensions.end())
            addLight(index, world, it->second);
        if (const auto it = node.extensions.find("VKPATH_sphere"); it != node.extensions.end())
            addSphere(index, world, it->second);
    }

    // ---- accessors -----------------------------------------------------------

    // The accessor's elements, tightly packed (count x element size), after
    // checking every offset, stride and count against the bufferView and the
    // buffer, and applying sparse substitution.
    std::vector<uint8_t> accessorBytes(int index, const std::string& what,
                                       size_t& elementSize) const {
        if (index < 0 || size_t(index) >= m_model.accessors.size())
            fail("{}: accessor {} does not exist", what, index);
        const tinygltf::Accessor& a = m_model.accessors[size_t(index)];
        const size_t compSize = componentSize(a.componentType);
        const size_t comps = componentCount(a.type);
        if (compSize == 0)
            fail("{}: accessor {} has invalid componentType {}", what, index, a.componentType);
        if (comps == 0) fail("{}: accessor {} has an invalid type", what, index);
        elementSize = compSize * comps;
        if (a.count == 0) fail("{}: accessor {} has count 0", what, index);
        if (a.count > MAX_ACCESSOR_COUNT)
            fail("{}: accessor {} count {} exceeds the limit of {}", what, index, a.count,
                 MAX_ACCESSOR_COUNT);

        if (a.bufferView < 0 && a.count > MAX_ZERO_ACCESSOR_COUNT)
            fail("{}: accessor {} has no bufferView and count {}, more than the {} allowed", what,
                 index, a.count, MAX_ZERO_ACCESSOR_COUNT);
        std::vector<uint8_t> out(a.count * elementSize,
                                 0);  // no bufferView: zeros (glTF 2.0, 3.6.2.1)
        if (a.bufferView >= 0) {
            size_t stride = 0;
            const std::span<const uint8_t> view = bufferView(a.bufferView, what, stride);
            if (stride == 0) stride = elementSize;
            if (stride < elementSize)
                fail("{}: accessor {} stride {} is smaller than its {}-byte elements", what, index,
                     stride, elementSize);
            const uint64_t needed =
                uint64_t(a.byteOffset) + uint64_t(a.count - 1) * stride + elementSize;
            if (a.byteOffset > view.size() || needed > view.size())
                fail(
                    "{}: accessor {} (offset {}, count {}, stride {}) overruns its bufferView {} "
                    "of {} bytes",
                    what, index, a.byteOffset, a.count, stride, a.bufferView, view.size());
            for (size_t i = 0; i < a.count; ++i)
                std::memcpy(&out[i * elementSize], view.data() + a.byteOffset + i * stride,
                            elementSize);
        }
        if (a.sparse.isSparse) applySparse(a, index, what, elementSize, out);
        return out;
    }

    // bufferView `index` as bytes, checked against its buffer.
    std::span<const uint8_t> bufferView(int index, const std::string& what, size_t& stride) const {
        if (index < 0 || size_t(index) >= m_model.bufferViews.size())
            fail("{}: bufferView {} does not exist", what, index);
        const tinygltf::BufferView& v = m_model.bufferViews[size_t(index)];
        if (v.buffer < 0 || size_t(v.buffer) >= m_model.buffers.size())
            fail("{}: bufferView {} refers to buffer {}, which does not exist", what, index,
                 v.buffer);
        const std::vector<unsigned char>& data = m_model.buffers[size_t(v.buffer)].data;
        if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset)
            fail("{}: bufferView {} (offset {}, length {}) overruns buffer {} of {} bytes", what,
                 index, v.byteOffset, v.byteLength, v.buffer, data.size());
        if (v.byteStride != 0 && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4 != 0))
            fail("{}: bufferView {} byteStride {} is not a multiple of 4 in [4, 252]", what, index,
                 v.byteStride);
        stride = v.byteStride;
        return std::span<const uint8_t>(data.data() + v.byteOffset, v.byteLength);
    }

    void applySparse(const tinygltf::Accessor& a, int index, const std::string& what,
                     size_t elementSize, std::vector<uint8_t>& out) const {
        const auto& sparse = a.sparse;
        if (sparse.count < 1 || size_t(sparse.count) > a.count)
            fail("{}: accessor {} sparse count {} is not in [1, {}]", what, index, sparse.count,
                 a.count);
        const size_t n = size_t(sparse.count);
        const size_t indexSize = componentSize(sparse.indices.componentType);
        if (indexSize == 0 || sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
            sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
            sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail("{}: accessor {} sparse indices must be unsigned integers", what, index);
        auto range = [&](int viewIndex, int offset, size_t bytes, const char* part) {
            size_t stride = 0;
            const std::span<const uint8_t> view = bufferView(viewIndex, what, stride);
            if (offset < 0 || size_t(offset) > view.size() || bytes > view.size() - size_t(offset))
                fail("{}: accessor {} sparse {} overrun bufferView {}", what, index, part,
                     viewIndex);
            return view.subspan(size_t(offset), bytes);
        };
        const auto indices =
            range(sparse.indices.bufferView, sparse.indices.byteOffset, n * indexSize, "indices");
        const auto values =
            range(sparse.values.bufferView, sparse.values.byteOffset, n * elementSize, "values");
        uint64_t previous = 0;
        for (size_t i = 0; i < n; ++i) {
            uint64_t target = 0;
            std::memcpy(&target, &indices[i * indexSize], indexSize);  // little-endian host
            if (target >= a.count || (i > 0 && target <= previous))
                fail("{}: accessor {} sparse index {} is out of range or not increasing", what,
                     index, target);
            std::memcpy(&out[target * elementSize], &values[i * elementSize], elementSize);
            previous = target;
        }
    }

    std::vector<glm::vec3> readVec3(int index, const std::string& what) const {
        if (index < 0 || size_t(index) >= m_model.accessors.size())
            fail("{}: accessor {} does not exist", what, index);
        const tinygltf::Accessor& a = m_model.accessors[size_t(index)];
        if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail("{}: accessor {} must be FLOAT VEC3, not {} {}", what, index, a.componentType,
                 typeName(a.type));
        size_t elementSize = 0;
        const std::vector<uint8_t> bytes = accessorBytes(index, what, elementSize);
        std::vector<glm::vec3> out(a.count);
        std::memcpy(out.data(), bytes.data(), bytes.size());
        for (size_t i = 0; i < out.size(); ++i)
            if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y) || !std::isfinite(out[i].z))
                fail("{}: element {} is not finite", what, i);
        return out;
    }

    std::vector<uint32_t> readIndices(int index, const std::string& what) const {
        if (index < 0 || size_t(index) >= m_model.accessors.size())
            fail("{}: accessor {} does not exist", what, index);
        const tinygltf::Accessor& a = m_model.accessors[size_t(index)];
        const int type = a.componentType;
        if (a.type != TINYGLTF_TYPE_SCALAR || (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                               type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                               type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            fail("{}: accessor {} must be an unsigned byte, short or int SCALAR", what, index);
        size_t elementSize = 0;
        const std::vector<uint8_t> bytes = accessorBytes(index, what, elementSize);
        std::vector<uint32_t> out(a.count);
        for (size_t i = 0; i < a.count; ++i) {
            uint32_t value = 0;
            std::memcpy(&value, &bytes[i * elementSize], elementSize);  // little-endian host
            out[i] = value;
        }
        return out;
    }

    // ---- meshes ----------------------------------------------------------------

    void addMesh(int nodeIndex, const glm::dmat4& world) {
        const tinygltf::Node& node = m_model.nodes[size_t(nodeIndex)];
        if (size_t(node.mesh) >= m_model.meshes.size())
            fail("{}: mesh {} does not exist", nodeName(nodeIndex), node.mesh);
        const tinygltf::Mesh& mesh = m_model.meshes[size_t(node.mesh)];
        const glm::dmat3 linear(world);
        const double det = glm::determinant(linear);
        const bool flip =
            det < 0.0;  // a mirroring transform turns counter-clockwise into clockwise
        const bool singular = !(std::abs(det) > 0.0) || !std::isfinite(det);
        const glm::dmat3 normalMatrix =
            singular ? glm::dmat3(0.0) : glm::transpose(glm::inverse(linear));
        const std::string baseName =
            !node.name.empty()
                ? node.name
                : (!mesh.name.empty() ? mesh.name : fmt::format("mesh {}", node.mesh));

        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& primitive = mesh.primitives[p];
            Mesh out;
            out.name = mesh.primitives.size() == 1 ? baseName : fmt::format("{}#{}", baseName, p);
            const std::string what = fmt::format("mesh '{}'", out.name);
            if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
                primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN)
                fail("{}: primitive mode {} ({}) is not supported; only the triangle modes TRIANGLES (4), "
                     "TRIANGLE_STRIP (5) and TRIANGLE_FAN (6) are",
                     what, primitive.mode, modeName(primitive.mode));
            const auto position = primitive.attributes.find("POSITION");
            if (position == primitive.attributes.end()) fail("{}: primitive has no POSITION", what);
            for (const auto& [attribute, accessor] : primitive.attributes) {
                if (attribute.rfind("COLOR_", 0) == 0)
                    m_warnings.add("vertex colours (COLOR_n) are ignored", "mesh", out.name);
                if (attribute.rfind("JOINTS_", 0) == 0 && node.skin < 0)
                    m_warnings.add("skins are ignored: meshes are used as bound", "mesh", out.name);
            }
            if (!primitive.targets.empty())
                m_warnings.add("morph targets are ignored", "mesh", out.name);

            const std::vector<glm::vec3> local = readVec3(position->second, what + " POSITION");
            out.positions.resize(local.size());
            for (size_t i = 0; i < local.size(); ++i) {
                const glm::dvec3 p3(world * glm::dvec4(glm::dvec3(local[i]), 1.0));
                if (!finite(p3) || !finite(glm::dvec3(glm::vec3(p3))))
                    fail("{}: position {} is not finite after the node transform", what, i);
                out.positions[i] = glm::vec3(p3);
            }

            if (const auto normal = primitive.attributes.find("NORMAL");
                normal != primitive.attributes.end()) {
                const std::vector<glm::vec3> normals = readVec3(normal->second, what + " NORMAL");
                if (normals.size() != local.size())
                    fail("{}: {} normals for {} positions", what, normals.size(), local.size());
                out.normals.resize(normals.size());
                bool usable = !singular;
                for (size_t i = 0; i < normals.size() && usable; ++i) {
                    const glm::dvec3 n = normalMatrix * glm::dvec3(normals[i]);
                    const double length = glm::length(n);
                    usable = length > 1e-12 && std::isfinite(length);
                    out.normals[i] = glm::vec3(n / length);
                }
                if (!usable) {
                    m_warnings.add("zero-length normals: face normals are used instead", "mesh",
                                   out.name);
                    out.normals.clear();
                }
            }

            std::vector<uint32_t> indices;
            if (primitive.indices >= 0) {
                indices = readIndices(primitive.indices, what + " indices");
            } else {
                indices.resize(local.size());
                for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
            }
            if (primitive.mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
                fail("{}: {} {} is not a multiple of 3", what,
                     primitive.indices >= 0 ? "index count" : "vertex count", indices.size());
            indices = triangleList(primitive.mode, std::move(indices));
            size_t degenerate = 0;
            for (size_t t = 0; t < indices.size(); t += 3) {
                glm::uvec3 tri(indices[t], indices[t + 1], indices[t + 2]);
                for (int k = 0; k < 3; ++k)
                    if (tri[k] >= local.size())
                        fail("{}: index {} is out of range ({} vertices)", what, tri[k],
                             local.size());
                const glm::vec3 a = out.positions[tri.x], b = out.positions[tri.y],
                                c = out.positions[tri.z];
                const float area = glm::length(glm::cross(b - a, c - a));
                if (!(area > 0.0f) || !std::isfinite(area)) {
                    ++degenerate;
                    continue;
                }
                if (flip) std::swap(tri.y, tri.z);
                out.triangles.push_back(tri);
            }
            if (degenerate > 0)
                m_warnings.add("degenerate triangles (zero area) are dropped", "triangle", out.name,
                               degenerate);
            if (out.triangles.empty()) continue;
            out.material = primitive.material < 0 ? defaultMaterial()
                                                  : materialIndex(primitive.material, what);
            m_scene.meshes.push_back(std::move(out));
        }
    }

    uint32_t materialIndex(int index, const std::string& what) const {
        if (index < 0 || size_t(index) >= m_model.materials.size())
            fail("{}: material {} does not exist", what, index);
        return uint32_t(index);  // glTF materials keep their indices in the scene
    }

    // ---- spheres ----------------------------------------------------------------

    void addSphere(int nodeIndex, const glm::dmat4& world, const tinygltf::Value& ext) {
        const std::string what = fmt::format("{}: VKPATH_sphere", nodeName(nodeIndex));
        if (!ext.IsObject()) fail("{} is not an object", what);
        const tinygltf::Value& radius = ext.Get("radius");
        if (!radius.IsNumber()) fail("{} needs a number 'radius'", what);
        const double r = radius.GetNumberAsDouble();
        if (!std::isfinite(r) || !(r > 0.0))
            fail("{}: radius {} is not a positive finite number", what, r);

        Sphere sphere;
        sphere.name = m_model.nodes[size_t(nodeIndex)].name;
        if (ext.Has("material")) {
            const tinygltf::Value& material = ext.Get("material");
            const double m = material.IsNumber() ? material.GetNumberAsDouble() : -1.0;
            if (m != std::floor(m) || m < 0.0 || m >= double(m_model.materials.size()))
                fail("{}: material is not the index of a material", what);
            sphere.material = uint32_t(m);
        } else {
            sphere.material = defaultMaterial();
        }
        const glm::dvec3 scales(glm::length(world[0]), glm::length(world[1]),
                                glm::length(world[2]));
        if (!finite(scales) || !(std::min({scales.x, scales.y, scales.z}) > 0.0))
            fail("{}: the node transform is singular", what);
        if (std::max({scales.x, scales.y, scales.z}) >
            std::min({scales.x, scales.y, scales.z}) * (1.0 + 1e-4))
            m_warnings.add(
                "spheres under a non-uniform scale keep their shape: the radius is scaled by the "
                "geometric mean",
                "sphere", sphere.name.empty() ? nodeName(nodeIndex) : sphere.name);
        const glm::dvec3 centre(world[3]);
        const double worldRadius = r * std::cbrt(scales.x * scales.y * scales.z);
        if (!finite(centre) || !std::isfinite(float(worldRadius)))
            fail("{}: not finite after the transform", what);
        sphere.center = glm::vec3(centre);
        sphere.radius = float(worldRadius);
        m_scene.spheres.push_back(sphere);
    }

    // ---- lights ----------------------------------------------------------------

    void addLight(int nodeIndex, const glm::dmat4& world, const tinygltf::Value& ext) {
        const std::string what = fmt::format("{}: KHR_lights_punctual", nodeName(nodeIndex));
        if (!ext.IsObject() || !ext.Get("light").IsInt()) fail("{} needs an integer 'light'", what);
        const int index = ext.Get("light").Get<int>();
        if (index < 0 || size_t(index) >= m_model.lights.size())
            fail("{}: light {} does not exist", what, index);
        const tinygltf::Light& light = m_model.lights[size_t(index)];
        const std::string name = light.name.empty() ? fmt::format("light {}", index) : light.name;

        glm::dvec3 color(1.0);
        if (!light.color.empty()) {
            if (light.color.size() != 3) fail("light '{}': color needs 3 numbers", name);
            color = glm::make_vec3(light.color.data());
        }
        if (!finite(color) || color.x < 0 || color.y < 0 || color.z < 0)
            fail("light '{}': color is not finite and non-negative", name);
        if (!std::isfinite(light.intensity) || light.intensity < 0)
            fail("light '{}': intensity {} is not finite and non-negative", name, light.intensity);
        if (light.range > 0.0)
            m_warnings.add(
                "light range is ignored: lights fall off with the inverse square forever", "light",
                name);
        // Photometric units taken as radiometric (docs/SCENES.md): cd as W/sr, lx as W/m^2.
        const glm::vec3 radiometric(color * light.intensity);
        const glm::vec3 position(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
        const glm::dvec3 axis =
            glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);  // lights point along their -Z
        if (!finite(glm::dvec3(position)) || !(glm::length(axis) > 0.0) || !finite(axis))
            fail("light '{}': the node transform is singular or not finite", name);
        const glm::vec3 direction(glm::normalize(axis));

        if (light.type == "point") {
            m_scene.pointLights.push_back({position, radiometric});
        } else if (light.type == "spot") {
            const double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
            if (!(inner >= 0.0 && inner < outer && outer <= glm::half_pi<double>()))
                fail(
                    "light '{}': cone angles inner {} and outer {} need 0 <= inner < outer <= pi/2",
                    name, inner, outer);
            m_scene.spotLights.push_back(
                {position, direction, radiometric, float(inner), float(outer)});
        } else if (light.type == "directional") {
            m_scene.directionalLights.push_back({direction, radiometric});
        } else {
            fail("light '{}': unknown type '{}'", name, light.type);
        }
    }

    // ---- camera ------------------------------------------------------------------

    void chooseCamera() {
        const CameraCandidate* chosen = nullptr;
        if (!m_options.cameraName.empty()) {
            std::vector<std::string> names;
            for (const CameraCandidate& c : m_cameras) {
                const std::string& cameraName = m_model.cameras[size_t(c.camera)].name;
                const std::string& nodeName = m_model.nodes[size_t(c.node)].name;
                if (cameraName == m_options.cameraName || nodeName == m_options.cameraName) {
                    chosen = &c;
                    break;
                }
                names.push_back("'" + (cameraName.empty() ? nodeName : cameraName) + "'");
            }
            if (!chosen)
                fail("no camera named '{}' (the scene has {})", m_options.cameraName,
                     names.empty() ? std::string("none")
                                   : fmt::format("{}", fmt::join(names, ", ")));
            if (m_model.cameras[size_t(chosen->camera)].type != "perspective")
                fail("camera '{}' is {}; only perspective cameras are supported",
                     m_options.cameraName, m_model.cameras[size_t(chosen->camera)].type);
        } else {
            for (const CameraCandidate& c : m_cameras) {
                if (m_model.cameras[size_t(c.camera)].type == "perspective") {
                    chosen = &c;
                    break;
                }
                m_warnings.add("orthographic cameras are not supported and are skipped", "camera",
                               m_model.cameras[size_t(c.camera)].name);
            }
        }
        if (!chosen) {
            m_scene.camera = frameBoundingBox();
            m_warnings.add("no perspective camera: a default camera frames the scene from +Z");
            return;
        }

        const tinygltf::Camera& gltf = m_model.cameras[size_t(chosen->camera)];
        Camera camera;
        camera.name = !gltf.name.empty() ? gltf.name : m_model.nodes[size_t(chosen->node)].name;
        const double yfov = gltf.perspective.yfov, aspect = gltf.perspective.aspectRatio;
        if (!(yfov > 0.0 && yfov < glm::pi<double>()))
            fail("camera '{}': yfov {} is not in (0, pi) radians", camera.name, yfov);
        if (!(aspect >= 0.0) || !std::isfinite(aspect))
            fail("camera '{}': aspectRatio {} is not positive", camera.name, aspect);
        // yfov is vertical; the scene model's field of view is horizontal for
        // the camera's own aspect. Without an aspect, treat the camera as
        // square (see gltf_loader.h).
        const double a = aspect > 0.0 ? aspect : 1.0;
        camera.xfovDegrees = float(glm::degrees(2.0 * std::atan(a * std::tan(yfov / 2.0))));
        camera.aspect = float(a);

        const glm::dmat4& world = chosen->world;
        const glm::dvec3 forward = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
        const glm::dvec3 up = glm::dmat3(world) * glm::dvec3(0.0, 1.0, 0.0);
        if (!(glm::length(forward) > 0.0) || !(glm::length(glm::cross(forward, up)) > 0.0) ||
            !finite(forward) || !finite(up))
            fail("camera '{}': the node transform is singular", camera.name);
        camera.position = glm::vec3(world[3]);
        camera.target = glm::vec3(glm::dvec3(world[3]) + glm::normalize(forward));
        camera.up = glm::vec3(glm::normalize(up));
        m_scene.camera = camera;
    }

    // A camera on the +Z side (glTF's "front") of the scene's bounding sphere,
    // looking at its centre, 40 degrees wide on both axes (aspect 1: a film of
    // any shape widens its narrower axis, so the sphere is never cropped).
    Camera frameBoundingBox() const {
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (const Mesh& m : m_scene.meshes)
            for (const glm::uvec3& t : m.triangles)
                for (int k = 0; k < 3; ++k) {
                    lo = glm::min(lo, m.positions[t[k]]);
                    hi = glm::max(hi, m.positions[t[k]]);
                }
        for (const Sphere& s : m_scene.spheres) {
            lo = glm::min(lo, s.center - s.radius);
            hi = glm::max(hi, s.center + s.radius);
        }
        const glm::vec3 centre = 0.5f * (lo + hi);
        const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
        const float distance =
            radius / std::sin(glm::radians(float(DEFAULT_CAMERA_FOV_DEGREES)) / 2.0f);
        Camera camera;
        camera.name = "default";
        camera.position = centre + glm::vec3(0.0f, 0.0f, distance);
        camera.target = centre;
        camera.up = {0.0f, 1.0f, 0.0f};
        camera.xfovDegrees = float(DEFAULT_CAMERA_FOV_DEGREES);
        camera.aspect = 1.0f;
        return camera;
    }

    std::string m_file;
    fs::path m_folder;  // the scene file's folder: external files must stay inside it
    const tinygltf::Model& m_model;
    const LoadOptions& m_options;
    Warnings m_warnings;
    Scene m_scene;
    std::optional<uint32_t> m_defaultMaterial;
    std::vector<CameraCandidate> m_cameras;  // in node order
};

}  // namespace

Scene loadGltf(const std::filesystem::path& path, const LoadOptions& options) {
    const std::string file = path.string();
    std::string error;
    const std::vector<uint8_t> bytes = readWholeFile(path, MAX_FILE_BYTES, error);
    if (!error.empty()) throw InputError(fmt::format("{}: {}", file, error));
    if (bytes.empty()) throw InputError(fmt::format("{}: file is empty", file));

    // Phase 1: the container. A GLB is recognised by its magic, whatever the extension.
    const bool binary = bytes.size() >= 4 && readU32(bytes, 0) == GLB_MAGIC;
    GlbChunks chunks;
    if (binary) {
        chunks = parseGlb(bytes, file);
    } else {
        chunks.json = bytes;
    }

    // Phase 2: the JSON and its URIs.
    Json root;
    try {
        root = Json::parse(chunks.json.begin(), chunks.json.end());
    } catch (const Json::exception& e) {  // parse errors, and numbers out of range (1e309)
        std::string message = e.what();
        if (const size_t bracket = message.find("] "); bracket != std::string::npos)
            message.erase(0, bracket + 2);
        throw InputError(fmt::format("{}: invalid JSON: {}", file, message));
    }
    if (!root.is_object())
        throw InputError(fmt::format("{}: not glTF: the JSON is not an object", file));
    const auto asset = root.find("asset");
    if (asset == root.end() || !asset->is_object() || !asset->contains("version") ||
        !(*asset)["version"].is_string())
        throw InputError(fmt::format("{}: not glTF: no asset.version", file));
    const std::string version = (*asset)["version"].get<std::string>();
    if (version.rfind("2.", 0) != 0)
        throw InputError(
            fmt::format("{}: glTF version {} is not supported (only 2.x)", file, version));
    // Before tinygltf: a required extension it cannot read either (Draco's
    // compressed buffers) makes it fail on the accessors, naming a bufferView
    // rather than the extension.
    if (const auto required = root.find("extensionsRequired"); required != root.end() && required->is_array())
        for (const Json& name : *required)
            if (name.is_string() && !SUPPORTED_EXTENSIONS.contains(name.get<std::string>()))
                throw InputError(fmt::format("{}: requires extension '{}', which vkpath does not support", file,
                                             name.get<std::string>()));
    fs::path folder = path.parent_path();
    if (folder.empty()) folder = ".";
    checkUris(root, folder, binary, chunks.hasBin, file);

    // Phase 3: tinygltf, reading files only inside the folder.
    std::error_code ec;
    FolderGuard guard{fs::canonical(folder, ec)};
    if (ec) throw InputError(fmt::format("{}: cannot resolve its folder: {}", file, ec.message()));
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(
        {&guardedFileExists, &unexpandedPath, &guardedReadWholeFile, &refuseWrite, &guard});
    loader.SetImageLoader(&keepImageUndecoded, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    const std::string baseDir = folder.string();
    const bool ok =
        binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                             static_cast<unsigned int>(bytes.size()), baseDir)
               : loader.LoadASCIIFromString(&model, &err, &warn,
                                            reinterpret_cast<const char*>(bytes.data()),
                                            static_cast<unsigned int>(bytes.size()), baseDir);
    if (!ok)
        throw InputError(
            fmt::format("{}: {}", file, err.empty() ? "tinygltf cannot load it" : oneLine(err)));

    // Phase 4.
    Scene scene = Importer(file, folder, model, options).run();
    scene.referencedFiles.insert(scene.referencedFiles.begin(), guard.read.begin(), guard.read.end());
    return scene;
}

}  // namespace vkpath::scene
