// glTF accessors read safely. tinygltf hands over buffers and accessor
// fields as the file states them; every offset, stride and count is checked
// here against its bufferView and buffer before a byte is read, sparse
// substitutions included, so a hostile file ends in one InputError line.
#pragma once

#include <fmt/format.h>
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "scene/gltf_container.h"

namespace vkpath::scene::gltf {

class Accessors {
  public:
    // `file` prefixes every error; `model` must outlive this.
    Accessors(const tinygltf::Model& model, std::string file)
        : m_model(model), m_file(std::move(file)) {}

    // FLOAT VEC3 elements, each finite. `what` names the data in errors
    // ("mesh 'box' POSITION").
    std::vector<glm::vec3> vec3(int index, const std::string& what) const;

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
