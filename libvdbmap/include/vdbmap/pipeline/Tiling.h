// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <openvdb/math/Coord.h>

#include "vdbmap/mesh/MarchingCubes.h"
#include "vdbmap/render/ViewFrustum.h"

namespace vdbmap {

class OptionSpec;
class VoxelMap;
class Dataset;

/// The optional `tiling:` section of a pipeline. With tile_size_m > 0 the stages that work on
/// the mesh (the first stage reading or writing the "mesh" layer and all after it) run once per
/// square ground tile on that tile's mesh plus a halo, instead of once on the whole map.
struct TilingConfig {
    double tile_size_m = 0.0;           ///< tile edge; 0 = untiled
    double halo_m = 4.0;                ///< border of neighbouring mesh each tile sees
    /// A view is given to a tile only if its frustum meets the tile within this depth.
    double max_view_distance_m = 40.0;
    /// Mesh around the tile (beyond the halo) used only as occluder by visibility tests.
    double occluder_margin_m = 30.0;
    bool merge = false;                 ///< also write today's single outputs (when they fit)
    std::int64_t merge_max_faces = 4000000;  ///< merge only up to this many faces
    /// The world axis that points up; tiles cut the other two. "auto": the W axis closest to
    /// the LiDAR's z axis at the first frame (KITTI's W is camera 0: y is up-down).
    std::string up_axis = "auto";
    /// Finish each tile as soon as no later scan or view can change it (while the scans are
    /// still being integrated); false: every tile after the last scan. Same outputs.
    bool stream = true;
    /// Finished tiles whose stages run side by side (after their marching cubes, in tasks
    /// beside the integration); 0 = auto (the number of threads). Bounded by memory_budget_gb.
    std::int64_t max_tiles_in_flight = 0;
    /// Cut the costliest tiles into pieces (TileGrid::split) until the tiles' estimated work
    /// spreads evenly over this many processes (TilePlan); 0 = never. The outputs depend on
    /// this value, not on the processes that run: a one-process run with the value an MPI run
    /// used writes the MPI run's outputs.
    std::int64_t split_for_processes = 0;
    /// Memory (GiB) the run keeps its tiles in flight within: a tile starts only while the
    /// process's memory without tiles plus the estimated peaks of the tiles in flight fit
    /// (one tile always runs); 0 = auto (half of MemAvailable at the start of the run). A
    /// tile whose estimate alone exceeds it is worked in pieces (TileGrid::split).
    double memory_budget_gb = 0.0;
    /// "whole": one map.vdb of the whole map at the end (the map is kept until then);
    /// "per_tile": each tile writes tiles/<name>/map.vdb (its core's leaves) when it is
    /// finished, and a streamed run drops the leaves no tile still to come reads, so that the
    /// map in memory stays that of the tiles around the sensor on a drive of any length.
    std::string map_vdb = "whole";

    bool enabled() const { return tile_size_m > 0.0; }
    bool mapPerTile() const { return map_vdb == "per_tile"; }
    void declareOptions(OptionSpec& spec);
    /// Throws ConfigError naming the key and the value: negative or non-finite values, a tile
    /// smaller than one voxel leaf (8 voxels of `voxel_size_m`), merge_max_faces < 0.
    /// `voxel_size_m` <= 0 skips the leaf check (voxel size unknown yet). up_axis must be
    /// auto, x, y or z.
    void validate(double voxel_size_m, const std::string& where) const;
};

/// "<ix>_<iy>", a tile's folder name below tiles/; a piece's is "<ix>_<iy>.<piece>".
inline std::string tileName(int ix, int iy, const std::string& piece = "") {
    return std::to_string(ix) + "_" + std::to_string(iy) + (piece.empty() ? "" : "." + piece);
}

/// A ground tile of a tiled run: its key, the cubes it owns (core) and sees (halo) on the voxel
/// grid, its bounds in the world frame and the views assigned to it. Tile edges lie on the
/// voxel-leaf grid (the edge is a whole number of 8-voxel leaves).
struct Tile {
    int ix = 0, iy = 0;
    MeshRegion region;        ///< voxel coordinates of cube min corners, ground axes
    MeshRegion occluder_region;  ///< region + occluder margin (halo_vox = the margin)
    double voxel_size_m = 0;
    int up_axis = 2;          ///< 0 = x, 1 = y, 2 = z
    /// Ground axes: the core. Up axis: the range of the map's leaves over the halo region
    /// (every face of the tile's mesh lies inside), the same whenever the tile is finished.
    Box3d core_W;
    Box3d halo_W;             ///< core grown by the halo
    /// (frame, camera) of every view that may see the tile (frustum, max view distance).
    std::vector<std::pair<std::size_t, std::size_t>> views;
    /// The tiling's max_view_distance_m the views were chosen with (for wider contexts).
    double max_view_distance_m = 40.0;
    /// Frames whose scans may change the map around the tile (its occluder region), ascending;
    /// empty when the run was not planned from the poses (TileGrid::tilesOf).
    std::vector<std::size_t> scan_frames;
    /// A piece of tile (ix, iy) (TileGrid::split: a tile whose estimated peak memory exceeded
    /// the budget): its path among the pieces, "2" or "2.0" (a piece of piece 2); "" for a
    /// whole tile.
    std::string piece;
    /// The estimated peaks (bytes) of the tile and of the pieces this piece was cut from,
    /// outermost first; empty for a whole tile.
    std::vector<std::size_t> split_estimates_bytes;

    /// "<ix>_<iy>", the tile's folder name below tiles/; a piece's is "<ix>_<iy>.<piece>".
    std::string name() const { return tileName(ix, iy, piece); }
    /// Distinct frames among the views.
    std::size_t numFrames() const;
};

/// The tiles of a map: the grid derived from the config and the voxel size, and the tiles
/// created on demand (every tile holding an observed leaf), sorted by (iy, ix).
class TileGrid {
public:
    /// `up_axis`: 0 = x, 1 = y, 2 = z (resolveUpAxis).
    TileGrid(const TilingConfig& config, double voxel_size_m, int up_axis);
    /// config.up_axis as an axis index; "auto" from the dataset's first LiDAR pose (z without
    /// a dataset).
    static int resolveUpAxis(const TilingConfig& config, const Dataset* dataset);
    int upAxis() const { return up_axis_; }
    std::int32_t tileVoxels() const { return tile_vox_; }
    std::int32_t haloVoxels() const { return halo_vox_; }
    double tileSizeM() const { return tile_vox_ * voxel_size_m_; }
    double haloM() const { return halo_vox_ * voxel_size_m_; }

    std::int32_t occluderVoxels() const { return occluder_vox_; }
    double voxelSize() const { return voxel_size_m_; }
    /// The two ground axes (0 = x, 1 = y, 2 = z): tile index ix runs along the first.
    int groundAxis(int k) const { return axes_[k]; }

    /// (ix, iy) of the tile holding voxel `ijk` (a leaf lies in one tile: edges are whole leaves).
    std::pair<int, int> tileOf(const openvdb::math::Coord& ijk) const {
        return {floorDiv(ijk[axes_[0]], tile_vox_), floorDiv(ijk[axes_[1]], tile_vox_)};
    }
    /// Tile (ix, iy) with its regions; its bounds along the up axis are empty until fitToMap.
    Tile tile(int ix, int iy) const;
    /// Sets the tile's bounds along the up axis from the leaves of `map` over its halo region
    /// (the region its mesh comes from). Returns whether its core holds an observed leaf.
    bool fitToMap(Tile& tile, const VoxelMap& map) const;
    /// Whether split() can cut the tile: its core is at least two voxel leaves wide along a
    /// ground axis.
    bool canSplit(const Tile& tile) const;
    /// The tile's core cut in halves (whole leaves) along each ground axis that is at least two
    /// leaves wide: 2 or 4 pieces, in (y, x) order, each with the tile's halo and occluder
    /// margin around its own core (the same halo rule as a tile), its scan frames, no views,
    /// bounds along the up axis empty until fitToMap. The pieces' cores partition the tile's.
    std::vector<Tile> split(const Tile& tile) const;
    /// The piece of tile (ix, iy) at `piece`, a path of split() ("2", "2.0"); the tile itself
    /// for "". Throws InvalidInput for a path split() does not make.
    Tile piece(int ix, int iy, const std::string& piece) const;
    /// Tiles holding at least one observed leaf of `map`, fitted to it, views not assigned.
    std::vector<Tile> tilesOf(const VoxelMap& map) const;
    /// Assigns to each tile every view of the dataset (frame x camera) whose frustum meets
    /// the tile's halo box within the depth `max_view_distance_m` (viewFrustumMeetsBox).
    static void assignViews(std::vector<Tile>& tiles, const Dataset& dataset,
                            double max_view_distance_m);
    /// The same for one tile and a list of views (datasetViews of the dataset).
    static void assignViews(Tile& tile, const std::vector<View>& views,
                            double max_view_distance_m);

private:
    static int floorDiv(std::int32_t a, std::int32_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

    double voxel_size_m_;
    int up_axis_;
    int axes_[2];
    std::int32_t tile_vox_;
    std::int32_t halo_vox_;
    std::int32_t occluder_vox_;
};

}  // namespace vdbmap
