#include "scene/collada_textures.h"

#include <fmt/format.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "scene/gltf_container.h"
#include "scene/texture_images.h"

namespace vkpath::scene::collada {
namespace {

namespace fs = std::filesystem;

// The limit on one image file, as the glTF importer's on each external file.
constexpr uint64_t MAX_FILE_BYTES = uint64_t(1) << 30;

std::string trimmed(std::string_view text) {
    auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (!text.empty() && space(text.front())) text.remove_prefix(1);
    while (!text.empty() && space(text.back())) text.remove_suffix(1);
    return std::string(text);
}

// Text from the file as it may appear in a one-line message: control
// characters (a newline inside an <init_from>) become '?'.
std::string printable(std::string text) {
    for (char& c : text)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return text;
}

// The effect's <newparam sid="sid">, in any of its profiles or techniques
// (sids are scoped to the effect).
pugi::xml_node newparam(pugi::xml_node effect, const std::string& sid) {
    return effect.find_node([&](pugi::xml_node n) {
        return std::string_view(n.name()) == "newparam" && sid == n.attribute("sid").as_string();
    });
}

// COLLADA's fx_sampler_wrap_common: WRAP (the default), MIRROR, CLAMP, and
// BORDER, NONE (1.4) and MIRROR_ONCE (1.5), which vkpath reads as CLAMP.
TextureWrap wrapMode(pugi::xml_node element, bool& approximated) {
    const std::string mode = trimmed(element.child_value());
    if (mode.empty() || mode == "WRAP") return TextureWrap::Repeat;
    if (mode == "MIRROR") return TextureWrap::MirroredRepeat;
    approximated = mode != "CLAMP";
    return TextureWrap::ClampToEdge;
}

}  // namespace

TextureRef TextureImporter::reference(pugi::xml_node texture, pugi::xml_node effect,
                                      const std::string& what) {
    const std::string name = texture.attribute("texture").as_string();
    if (name.empty()) m_document.fail(what + ": <texture> names no sampler (no texture attribute)");
    const std::string where = fmt::format("{}: <texture texture=\"{}\">", what, printable(name));

    pugi::xml_node imageElement, sampler;
    if (const pugi::xml_node param = newparam(effect, name); param.child("sampler2D")) {
        sampler = param.child("sampler2D");
        if (const pugi::xml_node instance = sampler.child("instance_image")) {  // COLLADA 1.5
            imageElement =
                m_document.resolve(instance.attribute("url").as_string(nullptr), "image", where);
        } else {
            const std::string source = trimmed(sampler.child_value("source"));
            const pugi::xml_node surface = newparam(effect, source).child("surface");
            if (!surface)
                m_document.fail(
                    fmt::format("{}: the sampler2D's <source> '{}' names no <surface> newparam",
                                where, printable(source)));
            const std::string id =
                std::string("#").append(trimmed(surface.child_value("init_from")));
            imageElement = m_document.resolve(id.c_str(), "image", where);
        }
    } else {
        // No sampler of that sid: some exporters name the <image> itself.
        const std::string id = std::string("#").append(name);
        imageElement = m_document.resolve(id.c_str(), "image", where);
    }

    TextureRef ref;
    const int32_t image = this->image(imageElement, what);
    if (image < 0) return ref;
    Texture t;
    t.image = uint32_t(image);
    bool approximated = false;
    t.wrapU = wrapMode(sampler.child("wrap_s"), approximated);
    t.wrapV = wrapMode(sampler.child("wrap_t"), approximated);
    // Bilinear unless NEAREST (absent, NONE and LINEAR alike; mipmaps are not
    // modelled, as for glTF).
    t.nearest = trimmed(sampler.child_value("magfilter")) == "NEAREST";
    if (approximated)
        m_warnings.addCounted("texture wrap modes BORDER, NONE and MIRROR_ONCE are read as CLAMP",
                              "texture", printable(name));
    for (size_t i = 0; i < m_scene.textures.size() && ref.texture < 0; ++i) {
        const Texture& o = m_scene.textures[i];
        if (o.image == t.image && o.wrapU == t.wrapU && o.wrapV == t.wrapV &&
            o.nearest == t.nearest)
            ref.texture = int32_t(i);
    }
    if (ref.texture < 0) {
        ref.texture = int32_t(m_scene.textures.size());
        m_scene.textures.push_back(t);
    }
    return ref;
}

int32_t TextureImporter::image(pugi::xml_node image, const std::string& what) {
    const std::string name = printable(nameOf(image));
    pugi::xml_node init = image.child("init_from");
    if (init.child("ref")) init = init.child("ref");  // COLLADA 1.5: <init_from><ref>
    const std::string uri = trimmed(init.child_value());
    if (uri.empty()) {
        m_warnings.addCounted(
            "images without a file (embedded <data> is not read) leave their textures out", "image",
            name);
        return -1;
    }
    if (uri.rfind("data:", 0) == 0)
        m_document.fail(fmt::format(
            "{}: image '{}': data: URIs are not read from COLLADA; give the image as a file "
            "beside the .dae",
            what, name));
    // The glTF importer's rule for external files. Its URI decoding is
    // tinygltf's, which reads '+' as a space; in a COLLADA URI '+' is '+'.
    std::string escaped;
    for (char c : uri) {
        if (c == '+')
            escaped += "%2B";
        else
            escaped.push_back(c);
    }
    fs::path folder = fs::path(m_document.file()).parent_path();
    if (folder.empty()) folder = ".";
    if (const std::string problem = gltf::uriProblem(escaped, folder); !problem.empty())
        m_document.fail(
            fmt::format("{}: image '{}': uri '{}' {}", what, name, printable(uri), problem));
    const fs::path path = folder / gltf::decodeUri(escaped);
    std::error_code ec;
    const std::string key = fs::canonical(path, ec).string();
    if (const auto it = m_images.find(key); it != m_images.end()) return it->second;

    const uintmax_t size = fs::file_size(path, ec);
    if (ec)
        m_document.fail(fmt::format("{}: image '{}': cannot read '{}': {}", what, name,
                                    path.string(), ec.message()));
    if (size > MAX_FILE_BYTES)
        m_document.fail(fmt::format("{}: image '{}': '{}' has {} bytes, more than the limit of {}",
                                    what, name, path.string(), size, MAX_FILE_BYTES));
    std::vector<uint8_t> bytes(size);
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
        m_document.fail(fmt::format("{}: image '{}': cannot read '{}'", what, name, path.string()));
    m_scene.referencedFiles.push_back(path.lexically_normal());
    const int32_t result = addTextureImage(m_scene, bytes, imageFormat(bytes, "", uri), name,
                                           m_document.file(), m_warnings);
    m_images[key] = result;
    return result;
}

}  // namespace vkpath::scene::collada
