// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>

#include <map>
#include <memory>
#include <string>

namespace vdbmap {

class BlockStatsGrid;

/// The volumetric map: OpenVDB grids sharing one linear transform of voxel size `voxelSize()`.
///  - `tsdf()`:   signed distance in metres, positive in front of the surface (towards the
///                sensor), background = +truncation max; saved as grid "surface".
///  - `weight()`: accumulated measurement weight, background 0 (= unobserved).
///  - per-8^3-leaf point statistics (count, mean, covariance) that drive the adaptive
///    truncation, see map/BlockStats.h.
///  - `extraGrids()`: further named grids written into map.vdb (e.g. "truncation", "label").
/// Coordinates are world frame W, metres. Voxel (i,j,k) has its centre at (i,j,k)*voxelSize.
class VoxelMap {
public:
    /// Throws InvalidInput if voxel_size_m is not finite and > 0.
    explicit VoxelMap(double voxel_size_m, float background_sdf_m = 1.0f);
    ~VoxelMap();
    VoxelMap(const VoxelMap&) = delete;
    VoxelMap& operator=(const VoxelMap&) = delete;

    double voxelSize() const { return voxel_size_m_; }
    openvdb::math::Transform::Ptr transform() const { return transform_; }

    openvdb::FloatGrid::Ptr tsdf() const { return tsdf_; }
    openvdb::FloatGrid::Ptr weight() const { return weight_; }

    BlockStatsGrid& blockStats() { return *block_stats_; }
    const BlockStatsGrid& blockStats() const { return *block_stats_; }

    /// Further grids saved into map.vdb. The name is the grid name in the file.
    void setExtraGrid(const std::string& name, openvdb::GridBase::Ptr grid);
    const std::map<std::string, openvdb::GridBase::Ptr>& extraGrids() const { return extra_; }

    /// File-level metadata written into map.vdb (e.g. "truncation_mode" = "adaptive").
    openvdb::MetaMap& metadata() { return meta_; }
    const openvdb::MetaMap& metadata() const { return meta_; }

private:
    double voxel_size_m_;
    openvdb::math::Transform::Ptr transform_;
    openvdb::FloatGrid::Ptr tsdf_;
    openvdb::FloatGrid::Ptr weight_;
    std::unique_ptr<BlockStatsGrid> block_stats_;
    std::map<std::string, openvdb::GridBase::Ptr> extra_;
    openvdb::MetaMap meta_;
};

}  // namespace vdbmap
