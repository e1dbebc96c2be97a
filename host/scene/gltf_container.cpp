#include "scene/gltf_container.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "input_error.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <nlohmann/json.hpp>
#pragma GCC diagnostic pop

namespace vkpath::scene::gltf {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr uint64_t MAX_FILE_BYTES = uint64_t(1) << 30;  // the scene file and each external file
constexpr uint32_t GLB_MAGIC = 0x46546C67;              // "glTF"
constexpr uint32_t GLB_CHUNK_JSON = 0x4E4F534A;         // "JSON"
constexpr uint32_t GLB_CHUNK_BIN = 0x004E4942;          // "BIN\0"

const std::set<std::string> SUPPORTED_EXTENSIONS = {
    "KHR_lights_punctual",        "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",    "KHR_materials_diffuse_transmission",
    "KHR_materials_dispersion",   "KHR_materials_emissive_strength",
    "KHR_materials_iridescence",  "KHR_materials_ior",
    "KHR_materials_sheen",        "KHR_materials_specular",
    "KHR_materials_transmission", "KHR_materials_variants",
    "KHR_materials_volume",       "KHR_materials_volume_scatter",
    "KHR_mesh_quantization",      "KHR_texture_transform",
    "VKPATH_environment",         "VKPATH_sphere",
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

bool isInside(const fs::path& canonicalPath, const fs::path& canonicalFolder) {
    auto p = canonicalPath.begin();
    for (auto f = canonicalFolder.begin(); f != canonicalFolder.end(); ++f, ++p) {
        if (f->empty()) continue;  // a trailing separator
        if (p == canonicalPath.end() || *p != *f) return false;
    }
    return true;
}

}  // namespace

bool extensionSupported(const std::string& name) {
    return SUPPORTED_EXTENSIONS.contains(name);
}

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

namespace {

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
                continue;  // an image's data URI is decoded by tinygltf, its bytes by gltf_textures
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

// tinygltf's image callback: keeps each image's bytes for the texture phase,
// which decodes only the images materials use, with OpenImageIO.
bool keepImageBytes(tinygltf::Image*, const int index, std::string*, std::string*, int, int,
                    const unsigned char* bytes, int size, void* user) {
    auto& images = *static_cast<std::vector<std::vector<uint8_t>>*>(user);
    if (index < 0) return true;
    if (size_t(index) >= images.size()) images.resize(size_t(index) + 1);
    if (bytes && size > 0) images[size_t(index)].assign(bytes, bytes + size);
    return true;
}

// tinygltf's messages end lines with '\n'; ours are one line.
std::string oneLine(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    for (size_t i; (i = text.find('\n')) != std::string::npos;) text.replace(i, 1, "; ");
    return text;
}

// Every glTF number is read as a 32-bit float or an integer: a number that
// is finite in the file but beyond a float's range (a node matrix's 5.6e88)
// would become an infinity in the scene, so it is bad input, named by its
// JSON pointer.
void checkNumbersFitFloats(const Json& root, const std::string& file) {
    std::vector<std::pair<const Json*, std::string>> stack{{&root, ""}};
    while (!stack.empty()) {
        const auto [value, pointer] = stack.back();
        stack.pop_back();
        if (value->is_object()) {
            for (const auto& [key, child] : value->items()) {
                std::string token;  // RFC 6901: ~ as ~0, / as ~1
                for (char c : key) token += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
                stack.push_back({&child, pointer + "/" + token});
            }
        } else if (value->is_array()) {
            for (size_t i = 0; i < value->size(); ++i)
                stack.push_back({&(*value)[i], pointer + "/" + std::to_string(i)});
        } else if (value->is_number_float()) {
            const double v = value->get<double>();
            if (std::abs(v) > double(std::numeric_limits<float>::max()))
                throw InputError(fmt::format("{}: {} is {:g}, beyond the range of a 32-bit float",
                                             file, pointer, v));
        }
    }
}

}  // namespace

Document readDocument(const std::filesystem::path& path) {
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
    checkNumbersFitFloats(root, file);
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
    if (const auto required = root.find("extensionsRequired");
        required != root.end() && required->is_array())
        for (const Json& name : *required)
            if (name.is_string() && !extensionSupported(name.get<std::string>()))
                throw InputError(
                    fmt::format("{}: requires extension '{}', which vkpath does not support", file,
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
    Document document;
    loader.SetImageLoader(&keepImageBytes, &document.imageBytes);
    document.folder = folder;
    std::string err, warn;
    const std::string baseDir = folder.string();
    const bool ok =
        binary ? loader.LoadBinaryFromMemory(&document.model, &err, &warn, bytes.data(),
                                             static_cast<unsigned int>(bytes.size()), baseDir)
               : loader.LoadASCIIFromString(&document.model, &err, &warn,
                                            reinterpret_cast<const char*>(bytes.data()),
                                            static_cast<unsigned int>(bytes.size()), baseDir);
    if (!ok)
        throw InputError(
            fmt::format("{}: {}", file, err.empty() ? "tinygltf cannot load it" : oneLine(err)));
    document.filesRead = std::move(guard.read);
    return document;
}

}  // namespace vkpath::scene::gltf
