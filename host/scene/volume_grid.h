// Heterogeneous media from OpenVDB grids (render --volume FILE.vdb): a float
// grid read with libopenvdb (Debian's libopenvdb-dev) and resampled into a
// dense array over its active voxels, which the kernels interpolate
// trilinearly as OpenVDB's BoxSampler does (docs/SCENES.md, "Media").
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

namespace vkpath::scene {

// A grid's voxels in world space: voxel (i, j, k) of the dense array is
// centred at origin + (i, j, k) * voxelSize, and the density between centres
// is trilinear. The array has a voxel of 0 around the grid's active voxels,
// so the density falls to 0 at its box, [origin, origin + (resolution - 1)
// voxelSize], and is 0 outside.
struct VolumeGrid {
    glm::uvec3 resolution{0};
    glm::dvec3 origin{0.0};
    glm::dvec3 voxelSize{1.0};
    // x fastest, then y, then z; shared: scenes are copied (moved into
    // render space) and the voxels need not be
    std::shared_ptr<const std::vector<float>> density;
    // The medium: sigma_t per metre = densityScale x the grid's value;
    // albedo sigma_s / sigma_t per channel; Henyey-Greenstein g.
    float densityScale = 1.0f;
    glm::vec3 albedo{1.0f};
    float anisotropy = 0.0f;

    float at(uint32_t i, uint32_t j, uint32_t k) const {
        return (*density)[(size_t(k) * resolution.y + j) * resolution.x + i];
    }
};

// The most voxels a grid's dense array may hold (1 GiB of floats).
inline constexpr uint64_t MAX_GRID_VOXELS = uint64_t(1) << 28;

// The float grid `gridName` of the .vdb file `path`, its transform a scale
// and translation (no rotation or shear). Throws InputError with one line
// naming the file for a file OpenVDB cannot read, a missing grid (listing
// the file's grids), a grid that is not of floats, a transform that turns,
// a negative or non-finite value, an empty grid, or one whose dense array
// would pass MAX_GRID_VOXELS.
VolumeGrid loadVolumeGrid(const std::filesystem::path& path, const std::string& gridName);

}  // namespace vkpath::scene
