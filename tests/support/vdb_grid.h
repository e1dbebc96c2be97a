// OpenVDB grid files for the tests of grid media (render --volume), written
// with libopenvdb.
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>
#include <glm/glm.hpp>

namespace vkpath::test {

// A .vdb file of one float grid "density" of voxels [0, n)^3 of size
// `voxel`, voxel (0, 0, 0) centred at `corner`, each of value(i, j, k).
inline std::filesystem::path writeGrid(const std::filesystem::path& path, int n, double voxel,
                                       glm::dvec3 corner,
                                       const std::function<float(int, int, int)>& value) {
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    openvdb::math::Transform::Ptr transform =
        openvdb::math::Transform::createLinearTransform(voxel);
    transform->postTranslate(openvdb::Vec3d(corner.x, corner.y, corner.z));
    grid->setTransform(transform);
    openvdb::FloatGrid::Accessor access = grid->getAccessor();
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) access.setValue(openvdb::Coord(i, j, k), value(i, j, k));
    openvdb::io::File(path.string()).write({grid});
    return path;
}

}  // namespace vkpath::test
