// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/VoxelMap.h"

#include <openvdb/tree/LeafManager.h>

#include <cmath>
#include <sstream>

#include "vdbmap/Error.h"
#include "vdbmap/map/BlockStats.h"

namespace vdbmap {

TsdfCodec::TsdfCodec(float sdf_range_m, float weight_range)
    : sdf_range_m_(sdf_range_m), weight_range_(weight_range) {
    if (!std::isfinite(sdf_range_m) || !(sdf_range_m > 0.0f) || !std::isfinite(weight_range) ||
        !(weight_range > 0.0f)) {
        std::ostringstream os;
        os << "TsdfCodec: the sdf range (m) and the weight range must be finite and > 0, got "
           << sdf_range_m << " and " << weight_range;
        throw InvalidInput(os.str());
    }
    sdf_quantum_m_ = sdf_range_m / 32767.0f;
    weight_quantum_ = weight_range / 65535.0f;
    inv_sdf_quantum_ = 1.0f / sdf_quantum_m_;
    inv_weight_quantum_ = 1.0f / weight_quantum_;
}

namespace {

TsdfCodec checkedCodec(double voxel_size_m, float sdf_range_m, float weight_range) {
    if (!std::isfinite(voxel_size_m) || voxel_size_m <= 0.0) {
        std::ostringstream os;
        os << "VoxelMap: voxel_size_m must be finite and > 0, got " << voxel_size_m;
        throw InvalidInput(os.str());
    }
    return TsdfCodec(sdf_range_m, weight_range);
}

/// A float grid with the topology of `tsdf` and its transform; fill(packed leaf, float leaf)
/// sets the values of the float leaf's active voxels (in parallel over leaves).
template <typename Fill>
openvdb::FloatGrid::Ptr decodedGrid(const TsdfGrid& tsdf, float background, Fill&& fill) {
    auto tree = std::make_shared<openvdb::FloatTree>(tsdf.tree(), background, openvdb::TopologyCopy());
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(*tree);
    leaves.foreach([&](openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
        fill(*tsdf.tree().probeConstLeaf(leaf.origin()), leaf);
    });
    auto grid = openvdb::FloatGrid::create(tree);
    grid->setTransform(tsdf.transform().copy());
    return grid;
}

}  // namespace

VoxelMap::VoxelMap(double voxel_size_m, float sdf_range_m, float weight_range)
    : voxel_size_m_(voxel_size_m), codec_(checkedCodec(voxel_size_m, sdf_range_m, weight_range)) {
    openvdb::initialize();
    // Voxel (i,j,k) has its centre at (i,j,k) * voxel size (OpenVDB cell-centred convention).
    transform_ = openvdb::math::Transform::createLinearTransform(voxel_size_m);
    tsdf_ = TsdfGrid::create(codec_.background());
    tsdf_->setTransform(transform_);
    tsdf_->setName("tsdf");
    block_stats_ = std::make_unique<BlockStatsGrid>();
}

VoxelMap::~VoxelMap() = default;

void VoxelMap::setVoxel(const openvdb::Coord& ijk, float sdf_m, float weight) {
    tsdf_->tree().setValueOn(ijk, codec_.encode(sdf_m, weight));
}

bool VoxelMap::probeVoxel(const openvdb::Coord& ijk, float& sdf_m, float& weight) const {
    std::uint32_t v = 0;
    const bool on = tsdf_->tree().probeValue(ijk, v);
    sdf_m = codec_.sdf(v);
    weight = codec_.weight(v);
    return on;
}

openvdb::Index64 VoxelMap::activeVoxelCount() const { return tsdf_->activeVoxelCount(); }

openvdb::Index64 VoxelMap::leafCount() const { return tsdf_->tree().leafCount(); }

std::size_t VoxelMap::tsdfMemoryBytes() const { return static_cast<std::size_t>(tsdf_->memUsage()); }

openvdb::FloatGrid::Ptr VoxelMap::surfaceGrid() const {
    auto grid = decodedGrid(*tsdf_, codec_.sdfRange(), [&](const TsdfLeaf& packed, auto& leaf) {
        for (auto it = leaf.beginValueOn(); it; ++it) it.setValue(codec_.sdf(packed.getValue(it.pos())));
    });
    grid->setName("surface");
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    return grid;
}

openvdb::FloatGrid::Ptr VoxelMap::weightGrid() const {
    auto grid = decodedGrid(*tsdf_, 0.0f, [&](const TsdfLeaf& packed, auto& leaf) {
        for (auto it = leaf.beginValueOn(); it; ++it) it.setValue(codec_.weight(packed.getValue(it.pos())));
    });
    grid->setName("weight");
    return grid;
}

openvdb::FloatGrid::Ptr VoxelMap::truncationGrid(float no_block_m) const {
    auto grid = decodedGrid(*tsdf_, no_block_m, [&](const TsdfLeaf&, auto& leaf) {
        const std::int32_t slot = block_stats_->find(BlockStatsGrid::blockOf(leaf.origin()));
        const float eps = slot >= 0 ? block_stats_->entry(slot).truncation_m : no_block_m;
        for (auto it = leaf.beginValueOn(); it; ++it) it.setValue(eps);
    });
    grid->setName("truncation");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    return grid;
}

void VoxelMap::setExtraGrid(const std::string& name, openvdb::GridBase::Ptr grid) {
    if (!grid) throw InvalidInput("VoxelMap::setExtraGrid: null grid '" + name + "'");
    if (name.empty() || name == "surface" || name == "weight" || name == "truncation") {
        throw InvalidInput("VoxelMap::setExtraGrid: reserved or empty grid name '" + name + "'");
    }
    grid->setName(name);
    extra_[name] = std::move(grid);
}

}  // namespace vdbmap
