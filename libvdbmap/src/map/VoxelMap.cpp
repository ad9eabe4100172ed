// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/VoxelMap.h"

#include <cmath>
#include <sstream>

#include "vdbmap/Error.h"
#include "vdbmap/map/BlockStats.h"

namespace vdbmap {

VoxelMap::VoxelMap(double voxel_size_m, float background_sdf_m) : voxel_size_m_(voxel_size_m) {
    if (!std::isfinite(voxel_size_m) || voxel_size_m <= 0.0) {
        std::ostringstream os;
        os << "VoxelMap: voxel_size_m must be finite and > 0, got " << voxel_size_m;
        throw InvalidInput(os.str());
    }
    if (!std::isfinite(background_sdf_m)) {
        throw InvalidInput("VoxelMap: background_sdf_m must be finite");
    }
    openvdb::initialize();
    // Voxel (i,j,k) has its centre at (i,j,k) * voxel size (OpenVDB cell-centred convention).
    transform_ = openvdb::math::Transform::createLinearTransform(voxel_size_m);
    tsdf_ = openvdb::FloatGrid::create(background_sdf_m);
    tsdf_->setTransform(transform_);
    tsdf_->setName("surface");
    tsdf_->setGridClass(openvdb::GRID_LEVEL_SET);
    weight_ = openvdb::FloatGrid::create(0.0f);
    weight_->setTransform(transform_);
    weight_->setName("weight");
    block_stats_ = std::make_unique<BlockStatsGrid>();
}

VoxelMap::~VoxelMap() = default;

void VoxelMap::setExtraGrid(const std::string& name, openvdb::GridBase::Ptr grid) {
    if (!grid) throw InvalidInput("VoxelMap::setExtraGrid: null grid '" + name + "'");
    if (name.empty() || name == "surface" || name == "weight") {
        throw InvalidInput("VoxelMap::setExtraGrid: reserved or empty grid name '" + name + "'");
    }
    grid->setName(name);
    extra_[name] = std::move(grid);
}

}  // namespace vdbmap
