// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/map/CompactTsdf.h"
#include "vdbmap/map/TsdfVoxel.h"

namespace vdbmap {

class BlockStatsGrid;

/// The volumetric map: OpenVDB grids sharing one linear transform of voxel size `voxelSize()`.
///  - the TSDF: 32-bit packed voxels (vdbmap/map/TsdfVoxel.h) holding the signed distance D
///    (metres, positive in front of the surface, towards the sensor; background +sdf range) and
///    the accumulated weight W (background 0 = unobserved). An active voxel is an observed one.
///    Each 8^3 leaf lives in one of two stores, never both:
///      `workingTsdf()`: an OpenVDB tree of dense leaves, the ones the integrator is updating;
///      `compactTsdf()`: the at-rest store, the observed voxels only (map/CompactTsdf.h).
///    The integrator moves leaves between them losslessly; `compact()` moves all to the
///    compact store (AtsdfIntegrator::finalize does). Read through TsdfReader, `leafViews()`,
///    `probeVoxel()`, or the decoded float grids of map.vdb (`surfaceGrid()`, `weightGrid()`).
///  - per-8^3-leaf point statistics (count, mean, covariance) that drive the adaptive
///    truncation, see map/BlockStats.h; `truncationGrid()` shows their eps per voxel.
///  - `extraGrids()`: further named grids written into map.vdb (e.g. "label").
/// Coordinates are world frame W, metres. Voxel (i,j,k) has its centre at (i,j,k)*voxelSize.
class VoxelMap {
public:
    /// Selects 8^3 leaves by their origin (a multiple of 8): the decoded grids of a part of
    /// the map (a tile's own map.vdb) and the leaves a long drive no longer needs.
    using LeafFilter = std::function<bool(const openvdb::Coord& origin)>;

    /// `sdf_range_m` bounds |D| (the integrator's truncation max must not exceed it) and is the
    /// background distance; `weight_range` bounds W (the integrator's max weight must not
    /// exceed it). Throws InvalidInput if voxel_size_m or a range is not finite and > 0.
    explicit VoxelMap(double voxel_size_m, float sdf_range_m = 1.0f, float weight_range = 100.0f);
    ~VoxelMap();
    VoxelMap(const VoxelMap&) = delete;
    VoxelMap& operator=(const VoxelMap&) = delete;

    double voxelSize() const { return voxel_size_m_; }
    /// Const accessors hand out const pointers only (stages get a const map in tiles).
    openvdb::math::Transform::ConstPtr transform() const { return transform_; }
    openvdb::math::Transform::Ptr transform() { return transform_; }

    /// The working tree of dense packed leaves, the compact store, and the codec.
    TsdfGrid::ConstPtr workingTsdf() const { return tsdf_; }
    TsdfGrid::Ptr workingTsdf() { return tsdf_; }
    const CompactTsdf& compactTsdf() const { return *compact_; }
    CompactTsdf& compactTsdf() { return *compact_; }
    const TsdfCodec& codec() const { return codec_; }

    /// Slow-path access to one voxel (tests, tools): set it observed with (sdf_m, weight), or
    /// read it; probeVoxel returns false for an unobserved voxel. setVoxel moves a compact
    /// leaf into the working tree first.
    void setVoxel(const openvdb::Coord& ijk, float sdf_m, float weight);
    bool probeVoxel(const openvdb::Coord& ijk, float& sdf_m, float& weight) const;

    /// The leaf with this origin (a multiple of 8) from whichever store holds it; mask ==
    /// nullptr: none. For one look-up; TsdfReader caches the leaf for many.
    TsdfLeafView leafView(const openvdb::Coord& origin) const;
    /// Every leaf of both stores (for parallel loops); the map must not change while in use.
    std::vector<TsdfLeafView> leafViews() const;
    /// visit(ijk, packed value) for every observed voxel of both stores (serial, leaf order).
    template <typename Visit>
    void forEachVoxel(Visit&& visit) const {
        for (const TsdfLeafView& leaf : leafViews())
            leaf.forEachObserved([&](openvdb::Index offset) {
                visit(leaf.origin + TsdfLeaf::offsetToLocalCoord(offset), leaf.value(offset));
            });
    }

    /// Leaves `created` were just added (empty) to the working tree: those that the compact
    /// store holds get their values back from it and leave it. Returns how many did.
    std::size_t reloadIntoWorking(const std::vector<TsdfLeaf*>& created);
    /// Moves the working leaves whose stamp (transientData) is below `min_stamp` to the compact
    /// store; leaves without an observed voxel are dropped. Returns how many moved.
    std::size_t retireWorking(std::uint32_t min_stamp);
    /// Moves every working leaf to the compact store (the map at rest).
    void compact();

    openvdb::Index64 activeVoxelCount() const;
    openvdb::Index64 leafCount() const;
    openvdb::Index64 workingLeafCount() const;
    /// Bytes of the TSDF, both stores (distance and weight; statistics excluded).
    std::size_t tsdfMemoryBytes() const;

    /// Decoded float grids with the topology of the TSDF, for map.vdb (docs/DATA.md) and
    /// inspection: "surface" (level set class, background +sdf range) and "weight" (background 0).
    /// With `keep`: only the leaves it accepts (nullptr or empty: all).
    openvdb::FloatGrid::Ptr surfaceGrid(const LeafFilter& keep = nullptr) const;
    openvdb::FloatGrid::Ptr weightGrid(const LeafFilter& keep = nullptr) const;
    /// "truncation": at every active voxel the eps of its 8^3 block after the last scan that
    /// merged points into it, or `no_block_m` for leaves whose block never held a point (they
    /// were written by the updates of a neighbouring block). Fog volume class.
    openvdb::FloatGrid::Ptr truncationGrid(float no_block_m, const LeafFilter& keep = nullptr) const;

    /// Removes the leaves `drop` accepts from both stores, with their block statistics (a
    /// tiled run drops the leaves that no tile still to come reads, docs/tiling.md). Not
    /// thread-safe; no scan may be in integration. Returns the TSDF leaves removed.
    std::size_t dropLeaves(const LeafFilter& drop);

    BlockStatsGrid& blockStats() { return *block_stats_; }
    const BlockStatsGrid& blockStats() const { return *block_stats_; }

    /// Further grids saved into map.vdb. The name is the grid name in the file.
    void setExtraGrid(const std::string& name, openvdb::GridBase::Ptr grid);
    std::map<std::string, openvdb::GridBase::ConstPtr> extraGrids() const {
        return {extra_.begin(), extra_.end()};
    }

    /// File-level metadata written into map.vdb (e.g. "truncation_mode" = "adaptive").
    openvdb::MetaMap& metadata() { return meta_; }
    const openvdb::MetaMap& metadata() const { return meta_; }

private:
    double voxel_size_m_;
    TsdfCodec codec_;
    openvdb::math::Transform::Ptr transform_;
    TsdfGrid::Ptr tsdf_;
    std::unique_ptr<CompactTsdf> compact_;
    std::unique_ptr<BlockStatsGrid> block_stats_;
    std::map<std::string, openvdb::GridBase::Ptr> extra_;
    openvdb::MetaMap meta_;
};

}  // namespace vdbmap
