// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// Point statistics of one 8^3 voxel block (paper Sec. 4.1): count n, mean E_mu and the
/// unbiased sample covariance C_sigma (divided by n - 1; zero for n <= 1). World frame, metres.
struct BlockStats {
    double n = 0.0;
    Vec3d mean = Vec3d::Zero();
    Mat3d cov = Mat3d::Zero();
};

/// Batch statistics of `points` (same convention as BlockStats). Empty input: n = 0.
BlockStats batchStats(const std::vector<Vec3d>& points);

/// Batch statistics of points[index[0]], ..., points[index[count - 1]] (same convention as
/// batchStats) in one pass over the points: sums of the points shifted by the first one, then
/// C = (S - n m m^T) / (n - 1) with m the shifted mean. Exact up to rounding, without the
/// cancellation of the unshifted one-pass form when the points lie close together (one block)
/// far from the origin. What the integrator merges per block and scan. count = 0: n = 0.
BlockStats batchStatsIndexed(const Vec3f* points, const std::uint32_t* index, std::size_t count);

/// Paper Eq. (1): merge of (n1, E_mu^1, C_sigma^1) and (n2, E_mu^2, C_sigma^2) into the
/// statistics of the union of both point sets. Either side may be empty (n = 0).
BlockStats mergeStats(const BlockStats& a, const BlockStats& b);

/// Local surface estimated from block statistics by PCA (paper Sec. 4.1).
struct PlaneEstimate {
    /// False for degenerate blocks: n < min_points, collinear points (lambda2 ~ 0) or all
    /// points equal (lambda2 = 0). Then `normal` is zero and `flatness` is 0.
    bool valid = false;
    /// Eigenvector of the smallest eigenvalue, oriented towards the sensor (paper Eq. (2)):
    /// v3 if v3 . (p_s - E_mu) > 0, else -v3. Unit length when valid.
    Vec3d normal = Vec3d::Zero();
    /// P_flat = 1 - lambda3 / lambda2 in [0, 1] (paper Eq. (3)).
    double flatness = 0.0;
    /// Eigenvalues lambda1 >= lambda2 >= lambda3 of the covariance (m^2).
    Vec3d eigenvalues = Vec3d::Zero();
};

/// PCA of `stats` with the normal oriented towards `sensor_W`. A block is degenerate when
/// n < min_points, or lambda2 <= collinear_ratio * lambda1 (collinear, includes lambda2 = 0),
/// or sqrt(lambda2) < min_spread_m (the points cover too little of the block, e.g. a ring that
/// clips its corner: the normal would be decided by the range noise).
/// The default 0.01 (spread across the line below 10% of the spread along it) also rejects a
/// single LiDAR ring crossing a block: its arc is nearly straight and, with range noise, the
/// smallest eigenvector would lie in the surface instead of along its normal.
PlaneEstimate estimatePlane(const BlockStats& stats, const Vec3d& sensor_W, int min_points,
                            double min_spread_m = 0.0, double collinear_ratio = 0.01);

/// What the integrator keeps per block: the statistics and the values derived from them after
/// the last merge (the truncation eps used for the points of that block, and the plane).
struct BlockEntry {
    BlockStats stats;
    Vec3f normal_W = Vec3f::Zero();  ///< oriented normal of the last estimate (zero: none)
    float flatness = 0.0f;           ///< P_flat of the last estimate
    float truncation_m = 0.0f;       ///< eps of the block after the last merge
    bool plane_valid = false;
};

/// Per-8^3-leaf statistics kept "next to the leaf": a block-resolution OpenVDB Int32 tree
/// whose voxel (bx, by, bz) is the TSDF leaf with origin 8 * (bx, by, bz); its value is the
/// index of the block's BlockEntry in a dense array (background -1 = no statistics).
/// Why this layout: a point costs one cached tree lookup (the Int32 tree has the same
/// sparse hierarchy as the TSDF, so a ValueAccessor hits its cache for consecutive LiDAR
/// points) and the entries are contiguous for the parallel per-block merge; no hand-written
/// hash and no change to the TSDF leaf type (which must stay a plain FloatGrid for map.vdb).
class BlockStatsGrid {
public:
    BlockStatsGrid();

    /// Block coordinate of the voxel `ijk` (floor division by 8: the TSDF leaf origin / 8).
    static openvdb::Coord blockOf(const openvdb::Coord& ijk) {
        return openvdb::Coord(ijk.x() >> 3, ijk.y() >> 3, ijk.z() >> 3);
    }

    /// Index of the block's entry, or -1.
    std::int32_t find(const openvdb::Coord& block) const;
    /// Index of the block's entry, created (zero statistics) if absent. Not thread-safe.
    std::int32_t findOrCreate(const openvdb::Coord& block);

    std::size_t size() const { return entries_.size(); }
    BlockEntry& entry(std::int32_t index) { return entries_[static_cast<std::size_t>(index)]; }
    const BlockEntry& entry(std::int32_t index) const {
        return entries_[static_cast<std::size_t>(index)];
    }
    /// Block coordinate of entry `index`.
    const openvdb::Coord& blockCoord(std::int32_t index) const {
        return coords_[static_cast<std::size_t>(index)];
    }
    /// Removes the entries of the blocks `erase` accepts; the others keep their statistics
    /// but may get new indices (no index may be held across the call). Returns how many.
    std::size_t eraseIf(const std::function<bool(const openvdb::Coord& block)>& erase);
    /// The index tree (block resolution).
    const openvdb::Int32Tree& indexTree() const { return index_tree_; }

    /// Bytes used: entries + coordinates + index tree.
    std::size_t memoryBytes() const;
    /// Bytes per block: sizeof(BlockEntry) + coordinate + the index tree amortised per block.
    double bytesPerBlock() const;

private:
    openvdb::Int32Tree index_tree_;
    std::vector<BlockEntry> entries_;
    std::vector<openvdb::Coord> coords_;
};

}  // namespace vdbmap
