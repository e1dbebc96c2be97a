// glTF accessors read safely. tinygltf hands over buffers and accessor
// fields as the file states them; every offset, stride and count is checked
// here against its bufferView and buffer before a byte is read, sparse
// substitutions included, so a hostile file ends in one InputError line.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "scene/gltf_container.h"

namespace vkpath::scene::gltf {

// How an accessor stores each component (glTF 2.0, 3.6.2.2).
struct Encoding {
    int componentType;  // TINYGLTF_COMPONENT_TYPE_*
    bool normalized;    // integers read as fractions of their range, not as their values
    bool operator==(const Encoding&) const = default;
};

// What an attribute's accessor may be: its element types and encodings.
struct AttributeFormat {
    std::vector<int> types;  // TINYGLTF_TYPE_*
    std::vector<Encoding> encodings;
};

// "FLOAT", "normalized UNSIGNED_BYTE", ...: how errors name an encoding.
std::string encodingName(const Encoding& encoding);
// "FLOAT, normalized UNSIGNED_BYTE or normalized UNSIGNED_SHORT VEC3 or VEC4".
std::string formatName(const AttributeFormat& format);

class Accessors {
  public:
    // `file` prefixes every error; `model` must outlive this.
    Accessors(const tinygltf::Model& model, std::string file)
        : m_model(model), m_file(std::move(file)) {}

    // The encoding of accessor `index`. `what` names the data in errors
    // ("mesh 'box' POSITION").
    Encoding encoding(int index, const std::string& what) const;

    // The elements of a vector accessor as floats, after checking its type
    // and encoding against `format`: FLOAT as stored, normalized integers as
    // glTF 2.0 3.11 converts them (c / 255, max(c / 127, -1), ...), other
    // integers as their values. Each element fills the first `components`
    // (which this sets) of a vec4, the rest 0. Every value is finite.
    std::vector<glm::vec4> floats(int index, const std::string& what, const AttributeFormat& format,
                                  size_t& components) const;

    // Unsigned byte, short or int SCALARs.
    std::vector<uint32_t> indices(int index, const std::string& what) const;

  private:
    template <typename... Args>
    [[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) const;

    const tinygltf::Accessor& accessor(int index, const std::string& what) const;
    std::vector<uint8_t> elementBytes(int index, const std::string& what,
                                      size_t& elementSize) const;
    std::span<const uint8_t> bufferView(int index, const std::string& what, size_t& stride) const;
    void applySparse(const tinygltf::Accessor& a, int index, const std::string& what,
                     size_t elementSize, std::vector<uint8_t>& out) const;

    const tinygltf::Model& m_model;
    std::string m_file;
};

}  // namespace vkpath::scene::gltf
