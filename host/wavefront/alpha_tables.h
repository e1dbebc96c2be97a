// The alpha test's table (shaders/shared/alpha.h): one MaterialAlpha per scene
// material, built only when some triangle's material can have holes.
#pragma once

#include <vector>

#include "scene/scene.h"
#include "shared/alpha.h"
#include "wavefront/texture_tables.h"

namespace vkpath::wavefront {

// Per scene material (index for index), or empty when no triangle needs the
// test. A MASK or BLEND material whose alpha is the same everywhere it can
// be seen and covers the whole surface (at least alphaCutoff for MASK, 1 for
// BLEND: the factor times the smallest alpha of its base-colour image's texels
// and of the COLOR_0 of the meshes that use it) is recorded as opaque: the
// test would pass every candidate. Spheres are opaque whatever their material.
std::vector<shared::MaterialAlpha> buildMaterialAlpha(const scene::Scene& scene,
                                                      const TextureTables& textures);

}  // namespace vkpath::wavefront
