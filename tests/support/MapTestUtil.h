// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "support/SimLidar.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/TriMesh.h"

/// Test helpers for the TSDF / meshing tests (H3).
namespace vdbmap::test {

/// Every observed voxel of the map as (coordinate, packed value), sorted: two maps are the same
/// map if these are equal.
inline std::vector<std::pair<openvdb::Coord, std::uint32_t>> voxelsOf(const VoxelMap& map) {
    std::vector<std::pair<openvdb::Coord, std::uint32_t>> out;
    map.forEachVoxel([&](const openvdb::Coord& c, std::uint32_t v) { out.emplace_back(c, v); });
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return out;
}

/// Integrates one simulated scan per pose into `map`; returns the summed stats.
inline IntegrationStats integrateScans(AtsdfIntegrator& integrator, const SimScene& scene,
                                       const SimLidarConfig& lidar,
                                       const std::vector<Isometry3d>& poses) {
    IntegrationStats total;
    for (std::size_t i = 0; i < poses.size(); ++i) {
        const auto points_L = simulateScan(scene, lidar, poses[i], i);
        total += integrator.integrateScan(points_L, poses[i]);
    }
    return total;
}

/// Number of mesh edges with fewer than two faces.
inline std::size_t boundaryEdgeCount(const TriMesh& mesh) {
    std::size_t n = 0;
    for (auto e : mesh.edges())
        if (mesh.is_boundary(e)) ++n;
    return n;
}

/// 14 sensor positions around `centre` at `distance`: 6 axis directions + 8 diagonals.
inline std::vector<Isometry3d> posesAround(const Vec3d& centre, double distance) {
    std::vector<Isometry3d> poses;
    std::vector<Vec3d> dirs = {Vec3d::UnitX(), -Vec3d::UnitX(), Vec3d::UnitY(),
                               -Vec3d::UnitY(), Vec3d::UnitZ(), -Vec3d::UnitZ()};
    for (int sx : {-1, 1})
        for (int sy : {-1, 1})
            for (int sz : {-1, 1}) dirs.push_back(Vec3d(sx, sy, sz).normalized());
    for (const Vec3d& d : dirs) {
        // Point the LiDAR's horizontal plane at the target: rotate z onto a direction
        // orthogonal to d so that the target lies at elevation 0.
        const Vec3d to_target = -d;
        Vec3d up = std::abs(to_target.z()) > 0.9 ? Vec3d::UnitX() : Vec3d::UnitZ();
        up = (up - up.dot(to_target) * to_target).normalized();
        const Vec3d x = to_target, z = up, y = z.cross(x);
        Isometry3d T = Isometry3d::Identity();
        T.linear().col(0) = x;
        T.linear().col(1) = y;
        T.linear().col(2) = z;
        T.translation() = centre + distance * d;
        poses.push_back(T);
    }
    return poses;
}

/// Max |a - b| over the union of active voxels of two grids (inactive reads background).
inline double maxGridDifference(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
    double diff = 0.0;
    auto acc_b = b.getConstAccessor();
    for (auto it = a.cbeginValueOn(); it; ++it)
        diff = std::max(diff, std::abs(static_cast<double>(*it) - acc_b.getValue(it.getCoord())));
    auto acc_a = a.getConstAccessor();
    for (auto it = b.cbeginValueOn(); it; ++it)
        diff = std::max(diff, std::abs(static_cast<double>(*it) - acc_a.getValue(it.getCoord())));
    return diff;
}

}  // namespace vdbmap::test
