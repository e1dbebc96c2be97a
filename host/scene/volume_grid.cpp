#include "scene/volume_grid.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "input_error.h"

namespace vkpath::scene {

VolumeGrid loadVolumeGrid(const std::filesystem::path& path, const std::string& gridName) {
    static std::once_flag initialized;
    std::call_once(initialized, [] { openvdb::initialize(); });
    const std::string file = path.string();
    auto fail = [&](const std::string& what) {
        throw InputError(fmt::format("{}: {}", file, what));
    };

    openvdb::GridBase::Ptr base;
    std::vector<std::string> names;
    try {
        openvdb::io::File vdb(file);
        vdb.open();
        for (auto it = vdb.beginName(); it != vdb.endName(); ++it) names.push_back(it.gridName());
        if (std::find(names.begin(), names.end(), gridName) != names.end())
            base = vdb.readGrid(gridName);
        vdb.close();
    } catch (const openvdb::Exception& e) {
        fail(fmt::format("not an OpenVDB file OpenVDB can read ({})", e.what()));
    }
    if (!base)
        fail(fmt::format("no grid named '{}' (the file has: {})", gridName,
                         names.empty() ? "none" : fmt::format("{}", fmt::join(names, ", "))));
    const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) fail(fmt::format("grid '{}' holds {}, not floats", gridName, base->valueType()));

    // The transform: index (i, j, k) to world, a scale per axis and a translation.
    const openvdb::math::Transform& transform = grid->transform();
    const openvdb::Vec3d zero = transform.indexToWorld(openvdb::Vec3d(0, 0, 0));
    glm::dvec3 scale;
    for (int axis = 0; axis < 3; ++axis) {
        openvdb::Vec3d unit(0, 0, 0);
        unit[axis] = 1;
        const openvdb::Vec3d step = transform.indexToWorld(unit) - zero;
        scale[axis] = step[axis];
        const double across = std::abs(step[(axis + 1) % 3]) + std::abs(step[(axis + 2) % 3]);
        if (!transform.isLinear() || !(step[axis] > 0) || across > 1e-9 * step[axis])
            fail(
                fmt::format("grid '{}': its transform turns, shears or mirrors the voxels; vkpath "
                            "reads grids whose transform is a scale and a translation",
                            gridName));
    }

    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (box.empty()) fail(fmt::format("grid '{}' has no active voxels", gridName));
    // One voxel of 0 around the active ones.
    const openvdb::Coord lo = box.min() - openvdb::Coord(1), hi = box.max() + openvdb::Coord(1);
    const glm::u64vec3 extent(hi.x() - lo.x() + 1, hi.y() - lo.y() + 1, hi.z() - lo.z() + 1);
    const uint64_t voxels = extent.x * extent.y * extent.z;
    if (voxels > MAX_GRID_VOXELS)
        fail(
            fmt::format("grid '{}': its active voxels span {} x {} x {}, {} voxels, more than the "
                        "{} vkpath holds",
                        gridName, extent.x, extent.y, extent.z, voxels, MAX_GRID_VOXELS));

    VolumeGrid out;
    out.resolution = glm::uvec3(extent);
    out.voxelSize = scale;
    const openvdb::Vec3d origin = transform.indexToWorld(lo);
    out.origin = glm::dvec3(origin.x(), origin.y(), origin.z());
    auto density = std::make_shared<std::vector<float>>(voxels, 0.0f);
    const openvdb::FloatGrid::ConstAccessor access = grid->getConstAccessor();
    for (int k = 1; k + 1 < int(extent.z); ++k)
        for (int j = 1; j + 1 < int(extent.y); ++j)
            for (int i = 1; i + 1 < int(extent.x); ++i) {
                const openvdb::Coord c = lo + openvdb::Coord(i, j, k);
                const float v = access.getValue(c);
                if (!std::isfinite(v) || v < 0.0f)
                    fail(
                        fmt::format("grid '{}': value {} at voxel ({}, {}, {}) is not a finite "
                                    "density >= 0",
                                    gridName, v, c.x(), c.y(), c.z()));
                (*density)[(size_t(k) * extent.y + j) * extent.x + i] = v;
            }
    out.density = std::move(density);
    return out;
}

}  // namespace vkpath::scene
