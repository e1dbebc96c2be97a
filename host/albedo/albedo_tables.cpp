#include "albedo/albedo_tables.h"

#include "shared/microfacet_albedo.h"

namespace vkpath::albedo {

namespace {
// make_albedo_tables' output, from the build folder.
constexpr float TABLE[] = {
#include "albedo/microfacet_albedo_table.inc"
};
static_assert(std::size(TABLE) == VKP_ALBEDO_TABLE_SIZE);
}  // namespace

std::span<const float> microfacetAlbedoTable() {
    return TABLE;
}

}  // namespace vkpath::albedo
