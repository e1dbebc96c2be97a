#include "scene/gltf_variants.h"

#include <fmt/format.h>

#include <algorithm>

#include "input_error.h"

namespace vkpath::scene::gltf {

namespace {

constexpr const char* EXTENSION = "KHR_materials_variants";

template <typename... Args>
[[noreturn]] void fail(const std::string& file, fmt::format_string<Args...> format,
                       Args&&... args) {
    throw InputError(fmt::format("{}: {}: {}", file, EXTENSION,
                                 fmt::format(format, std::forward<Args>(args)...)));
}

// The variant names of the root's extension.
std::vector<std::string> variantNames(const tinygltf::Model& model, const std::string& file) {
    const auto it = model.extensions.find(EXTENSION);
    if (it == model.extensions.end()) return {};
    const tinygltf::Value& variants = it->second.Get("variants");
    if (!variants.IsArray() || variants.ArrayLen() == 0)
        fail(file, "'variants' is not a non-empty array");
    std::vector<std::string> names;
    for (size_t i = 0; i < variants.ArrayLen(); ++i) {
        const tinygltf::Value& name = variants.Get(int(i)).Get("name");
        if (!name.IsString() || name.Get<std::string>().empty())
            fail(file, "variant {} has no name", i);
        if (std::find(names.begin(), names.end(), name.Get<std::string>()) != names.end())
            fail(file, "two variants are named '{}'", name.Get<std::string>());
        names.push_back(name.Get<std::string>());
    }
    return names;
}

// An index in [0, count) at `value`, or the error naming `what`.
int checkedIndex(const tinygltf::Value& value, size_t count, const std::string& file,
                 const std::string& what) {
    if (!value.IsInt() || value.Get<int>() < 0 || size_t(value.Get<int>()) >= count)
        fail(file, "{} is not an index below {}", what, count);
    return value.Get<int>();
}

}  // namespace

std::vector<std::string> applyMaterialVariant(tinygltf::Model& model, const std::string& chosen,
                                              const std::string& file) {
    const std::vector<std::string> names = variantNames(model, file);
    int wanted = -1;
    if (!chosen.empty()) {
        const auto it = std::find(names.begin(), names.end(), chosen);
        if (it == names.end()) {
            if (names.empty())
                throw InputError(fmt::format("{}: no material variants ({}) to choose '{}' from",
                                             file, EXTENSION, chosen));
            std::string list;
            for (const std::string& name : names) list += (list.empty() ? "'" : ", '") + name + "'";
            throw InputError(fmt::format("{}: no material variant named '{}' (the file's: {})",
                                         file, chosen, list));
        }
        wanted = int(it - names.begin());
    }
    for (size_t m = 0; m < model.meshes.size(); ++m)
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            tinygltf::Primitive& primitive = model.meshes[m].primitives[p];
            const auto it = primitive.extensions.find(EXTENSION);
            if (it == primitive.extensions.end()) continue;
            const std::string where = fmt::format("mesh {} primitive {}", m, p);
            if (names.empty()) fail(file, "{} maps variants the file does not declare", where);
            const tinygltf::Value& mappings = it->second.Get("mappings");
            if (!mappings.IsArray()) fail(file, "{}: 'mappings' is not an array", where);
            for (size_t i = 0; i < mappings.ArrayLen(); ++i) {
                const tinygltf::Value& mapping = mappings.Get(int(i));
                const std::string at = fmt::format("{} mapping {}", where, i);
                const int material = checkedIndex(mapping.Get("material"), model.materials.size(),
                                                  file, at + " material");
                const tinygltf::Value& variants = mapping.Get("variants");
                if (!variants.IsArray() || variants.ArrayLen() == 0)
                    fail(file, "{}: 'variants' is not a non-empty array", at);
                for (size_t v = 0; v < variants.ArrayLen(); ++v)
                    if (checkedIndex(variants.Get(int(v)), names.size(), file, at + " variant") ==
                        wanted)
                        primitive.material = material;
            }
        }
    return names;
}

}  // namespace vkpath::scene::gltf
