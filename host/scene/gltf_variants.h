// glTF's KHR_materials_variants: a file may name sets of materials
// ("variants": the colours of a product) and map each primitive to another
// material per variant. vkpath renders the primitives' own materials unless
// one variant is chosen (LoadOptions::materialVariant, `render --variant`).
#pragma once

#include <string>
#include <vector>

#include "scene/gltf_container.h"

namespace vkpath::scene::gltf {

// The names of the variants `model` declares (none without the extension),
// after checking the extension everywhere: the root's list of named
// variants, each primitive's mappings (a material that exists, variants
// that do). With `chosen` non-empty, each primitive whose mappings list that
// variant takes the mapping's material. Throws InputError ("<file>: ...",
// one line) on a malformed extension and on a name the file does not declare
// (the line lists the names it does).
std::vector<std::string> applyMaterialVariant(tinygltf::Model& model, const std::string& chosen,
                                              const std::string& file);

}  // namespace vkpath::scene::gltf
