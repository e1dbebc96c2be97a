#include "scene/load.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <system_error>

#include "input_error.h"
#include "scene/collada_loader.h"
#include "scene/gltf_loader.h"

namespace vkpath::scene {
namespace {

std::string lowercaseExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

// The checks every format shares, so each importer may assume a readable,
// non-empty regular file and every format reports these the same way.
void checkReadableFile(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status)) throw InputError(fmt::format("{}: no such file", file));
    if (std::filesystem::is_directory(status))
        throw InputError(fmt::format("{}: is a directory, not a scene file", file));
    if (!std::filesystem::is_regular_file(status))
        throw InputError(fmt::format("{}: not a regular file", file));
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(fmt::format("{}: cannot read: {}", file, ec.message()));
    if (size == 0) throw InputError(fmt::format("{}: file is empty", file));
}

}  // namespace

Scene loadScene(const std::filesystem::path& path, const LoadOptions& options) {
    checkReadableFile(path);
    const std::string ext = lowercaseExtension(path);
    if (ext == ".dae" && !options.materialVariant.empty())
        throw InputError(
            fmt::format("{}: no material variants to choose '{}' from: COLLADA has none (glTF's "
                        "KHR_materials_variants)",
                        path.string(), options.materialVariant));
    if (ext == ".dae") return loadCollada(path, options);
    if (ext == ".gltf" || ext == ".glb") return loadGltf(path, options);
    throw InputError(fmt::format("{}: unknown scene format '{}' (expected .gltf, .glb or .dae)",
                                 path.string(), ext));
}

}  // namespace vkpath::scene
