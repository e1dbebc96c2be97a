// The microfacet albedo tables (shaders/shared/microfacet_albedo.h), written
// at build time by make_albedo_tables.cpp: what multiple-scattering
// compensation reads, uploaded as the scene array microfacetAlbedo.
#pragma once
#include <span>

namespace vkpath::albedo {

// VKP_ALBEDO_TABLE_SIZE floats in the layout of shared/microfacet_albedo.h.
std::span<const float> microfacetAlbedoTable();

}  // namespace vkpath::albedo
