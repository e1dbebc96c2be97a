// The first phases of the glTF importer, up to tinygltf's model: the file,
// the GLB container, the URI guard and tinygltf itself. The later phases
// (gltf_loader.cpp and the files it calls) read only the model, never the
// file system, except the environment map of VKPATH_environment, held to the
// same URI rule.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

// Third-party headers: their warnings are not ours (-Werror).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
// The shared library libtinygltf carries the implementation (with stb_image
// and nlohmann/json); the header alone only declares it, so no
// TINYGLTF_IMPLEMENTATION and no STB/JSON defines here.
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace vkpath::scene::gltf {

struct Document {
    tinygltf::Model model;
    std::filesystem::path folder;  // the scene file's folder: external files must stay inside it
    std::vector<std::filesystem::path> filesRead;  // what tinygltf read (buffers, images), in order
    // Per glTF image, its file's bytes as tinygltf found them (a file, a data
    // URI or a bufferView), not yet decoded: the texture phase decodes those
    // a material uses (gltf_textures). Empty where tinygltf had none.
    std::vector<std::vector<uint8_t>> imageBytes;
};

// Reads `path` (.gltf or .glb, told apart by the GLB magic):
//   1. the file and, for .glb, the container (lengths, chunk types,
//      alignment), checked here: tinygltf's GLB checks have had gaps;
//   2. the JSON, parsed once to refuse unsupported required extensions and
//      to check every buffer/image URI before tinygltf touches the file
//      system: no scheme, not absolute, no "..", present, and not a symbolic
//      link out of the folder;
//   3. tinygltf's model, read through file-system callbacks that enforce the
//      same rule and never write (images are kept as bytes, Document::imageBytes).
// Throws InputError "<file>: <problem>" on anything malformed or unsafe.
Document readDocument(const std::filesystem::path& path);

// Whether vkpath models the meaning of the extension `name`; any other one
// is warned about when used and refused when required.
bool extensionSupported(const std::string& name);

// `uri` decoded as tinygltf decodes it before it opens a file.
std::string decodeUri(const std::string& uri);

// Why the file URI `uri` may not be read from `folder`, or "" when it may.
std::string uriProblem(const std::string& uri, const std::filesystem::path& folder);

}  // namespace vkpath::scene::gltf
