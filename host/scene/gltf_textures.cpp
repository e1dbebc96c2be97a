#include "scene/gltf_textures.h"

#include <fmt/format.h>

#include <cmath>
#include <span>

#include "input_error.h"
#include "scene/texture_images.h"

namespace vkpath::scene::gltf {
namespace {

// glTF 2.0 section 5.26 (sampler): the OpenGL enums.
TextureWrap wrapMode(int gl) {
    switch (gl) {
        case 33071:
            return TextureWrap::ClampToEdge;
        case 33648:
            return TextureWrap::MirroredRepeat;
        default:
            return TextureWrap::Repeat;  // 10497, and the default when absent
    }
}

constexpr int GL_NEAREST = 9728;

// A number of an extension object, `fallback` when absent.
double number(const tinygltf::Value& object, const char* key, double fallback,
              const std::string& where) {
    if (!object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
        throw InputError(
            fmt::format("{}: KHR_texture_transform.{} is not a finite number", where, key));
    return v.GetNumberAsDouble();
}

glm::vec2 pair(const tinygltf::Value& object, const char* key, glm::vec2 fallback,
               const std::string& where) {
    if (!object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
        throw InputError(
            fmt::format("{}: KHR_texture_transform.{} is not two numbers", where, key));
    const glm::dvec2 d(v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble());
    if (!std::isfinite(d.x) || !std::isfinite(d.y))
        throw InputError(fmt::format("{}: KHR_texture_transform.{} is not finite", where, key));
    return glm::vec2(d);
}

}  // namespace

TextureImporter::TextureImporter(const Document& document, const std::string& file, Scene& scene,
                                 ImportWarnings& warnings)
    : m_document(document), m_file(file), m_scene(scene), m_warnings(warnings) {}

TextureRef TextureImporter::reference(int index, int texCoord,
                                      const tinygltf::ExtensionMap& extensions,
                                      const std::string& material, const char* use) {
    TextureRef ref;
    if (index < 0) return ref;
    const std::string where = fmt::format("{}: material '{}': {}", m_file, material, use);
    if (const auto it = extensions.find("KHR_texture_transform"); it != extensions.end()) {
        const tinygltf::Value& t = it->second;
        if (!t.IsObject()) throw InputError(where + ": KHR_texture_transform is not an object");
        ref.offset = pair(t, "offset", glm::vec2(0.0f), where);
        ref.rotation = float(number(t, "rotation", 0.0, where));
        ref.scale = pair(t, "scale", glm::vec2(1.0f), where);
        texCoord =
            int(number(t, "texCoord", texCoord, where));  // the extension's texCoord overrides
    }
    if (texCoord != 0 && texCoord != 1) {
        m_warnings.addCounted(
            "textures read from TEXCOORD_2 and beyond are ignored (vkpath keeps two sets)",
            "material", material);
        return ref;
    }
    ref.texCoord = uint32_t(texCoord);
    ref.texture = texture(index, material, use);
    return ref;
}

int32_t TextureImporter::texture(int index, const std::string& material, const char* use) {
    const tinygltf::Model& model = m_document.model;
    if (size_t(index) >= model.textures.size())
        throw InputError(fmt::format("{}: material '{}': {} names texture {}, of {}", m_file,
                                     material, use, index, model.textures.size()));
    if (const auto it = m_textures.find(index); it != m_textures.end()) return it->second;
    const tinygltf::Texture& t = model.textures[size_t(index)];
    // The core source, or one of the extensions that name another (WebP, Basis Universal).
    int source = t.source;
    for (const char* extension : {"EXT_texture_webp", "KHR_texture_basisu"}) {
        const auto it = t.extensions.find(extension);
        if (source < 0 && it != t.extensions.end() && it->second.IsObject() &&
            it->second.Has("source") && it->second.Get("source").IsInt())
            source = it->second.Get("source").GetNumberAsInt();
    }
    int32_t result = -1;
    if (source < 0 || size_t(source) >= model.images.size()) {
        if (source >= 0)
            throw InputError(fmt::format("{}: texture {} names image {}, of {}", m_file, index,
                                         source, model.images.size()));
        m_warnings.addCounted("textures without an image are ignored", "texture",
                              std::to_string(index));
    } else if (const int32_t image = this->image(source); image >= 0) {
        Texture texture;
        texture.image = uint32_t(image);
        if (t.sampler >= 0) {
            if (size_t(t.sampler) >= model.samplers.size())
                throw InputError(fmt::format("{}: texture {} names sampler {}, of {}", m_file,
                                             index, t.sampler, model.samplers.size()));
            const tinygltf::Sampler& s = model.samplers[size_t(t.sampler)];
            texture.wrapU = wrapMode(s.wrapS);
            texture.wrapV = wrapMode(s.wrapT);
            texture.nearest = s.magFilter == GL_NEAREST;
        }
        result = int32_t(m_scene.textures.size());
        m_scene.textures.push_back(texture);
    }
    m_textures[index] = result;
    return result;
}

int32_t TextureImporter::image(int index) {
    if (const auto it = m_images.find(index); it != m_images.end()) return it->second;
    const tinygltf::Image& source = m_document.model.images[size_t(index)];
    const std::string name = source.name.empty() ? fmt::format("image {}", index) : source.name;
    static const std::vector<uint8_t> none;
    const std::vector<uint8_t>& bytes =
        size_t(index) < m_document.imageBytes.size() ? m_document.imageBytes[size_t(index)] : none;
    const int32_t result = addTextureImage(
        m_scene, bytes, imageFormat(bytes, source.mimeType, source.uri), name, m_file, m_warnings);
    m_images[index] = result;
    return result;
}

}  // namespace vkpath::scene::gltf
