#include "scene/texture_images.h"

#include <fmt/format.h>

#include <cctype>
#include <initializer_list>

#include "image/image.h"
#include "input_error.h"

namespace vkpath::scene {
namespace {

bool startsWith(const std::vector<uint8_t>& bytes, std::initializer_list<int> magic,
                size_t at = 0) {
    if (bytes.size() < at + magic.size()) return false;
    size_t i = at;
    for (int m : magic)
        if (bytes[i++] != uint8_t(m)) return false;
    return true;
}

}  // namespace

std::string imageFormat(const std::vector<uint8_t>& bytes, const std::string& mimeType,
                        const std::string& uri) {
    if (startsWith(bytes, {0x89, 'P', 'N', 'G'})) return "png";
    if (startsWith(bytes, {0xFF, 0xD8, 0xFF})) return "jpg";
    if (startsWith(bytes, {'R', 'I', 'F', 'F'}) && startsWith(bytes, {'W', 'E', 'B', 'P'}, 8))
        return "webp";
    if (startsWith(bytes, {0xAB, 'K', 'T', 'X', ' ', '2', '0'})) return "ktx2";
    if (mimeType == "image/png") return "png";
    if (mimeType == "image/jpeg") return "jpg";
    if (mimeType == "image/webp") return "webp";
    if (mimeType == "image/ktx2") return "ktx2";
    // TGA and others without a magic number at the start: the name says.
    const size_t dot = uri.find_last_of('.');
    if (dot != std::string::npos && uri.rfind("data:", 0) != 0) {
        std::string extension = uri.substr(dot + 1);
        for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
        return extension;
    }
    return "";
}

int32_t addTextureImage(Scene& scene, const std::vector<uint8_t>& bytes, const std::string& format,
                        const std::string& name, const std::string& file,
                        ImportWarnings& warnings) {
    image::Rgba16Image decoded;
    try {
        if (bytes.empty()) throw InputError("it has no data");
        if (format.empty()) throw InputError("its format is unknown");
        decoded = image::decodeImage(bytes, format, MAX_IMAGE_PIXELS);
    } catch (const InputError& e) {
        warnings.addCounted(
            fmt::format("images that cannot be decoded ({}) leave their textures out",
                        format.empty() ? "unknown format" : format),
            "image", fmt::format("{} ({})", name, e.what()));
        return -1;
    }
    uint64_t texels = decoded.texels.size();
    for (const TextureImage& i : scene.images) texels += i.texels.size();
    if (texels > MAX_SCENE_TEXELS)
        throw InputError(
            fmt::format("{}: textures need more than {} MiB on the device, vkpath's budget for "
                        "textures ({} texels); image '{}' is past it",
                        file, MAX_SCENE_TEXELS * 8 >> 20, MAX_SCENE_TEXELS, name));
    TextureImage image;
    image.name = name;
    image.width = decoded.width;
    image.height = decoded.height;
    image.texels = std::move(decoded.texels);
    scene.images.push_back(std::move(image));
    return int32_t(scene.images.size() - 1);
}

}  // namespace vkpath::scene
