// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

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
    double max_view_distance_m = 60.0;  ///< a view is given to a tile only within this distance
    /// Mesh around the tile (beyond the halo) used only as occluder by visibility tests.
    double occluder_margin_m = 30.0;
    bool merge = false;                 ///< also write today's single outputs (when they fit)
    std::int64_t merge_max_faces = 4000000;  ///< merge only up to this many faces
    /// The world axis that points up; tiles cut the other two. "auto": the W axis closest to
    /// the LiDAR's z axis at the first frame (KITTI's W is camera 0: y is up-down).
    std::string up_axis = "auto";

    bool enabled() const { return tile_size_m > 0.0; }
    void declareOptions(OptionSpec& spec);
    /// Throws ConfigError naming the key and the value: negative or non-finite values, a tile
    /// smaller than one voxel leaf (8 voxels of `voxel_size_m`), merge_max_faces < 0.
    /// `voxel_size_m` <= 0 skips the leaf check (voxel size unknown yet). up_axis must be
    /// auto, x, y or z.
    void validate(double voxel_size_m, const std::string& where) const;
};

/// A ground tile of a tiled run: its key, the cubes it owns (core) and sees (halo) on the voxel
/// grid, its bounds in the world frame and the views assigned to it. Tile edges lie on the
/// voxel-leaf grid (the edge is a whole number of 8-voxel leaves).
struct Tile {
    int ix = 0, iy = 0;
    MeshRegion region;        ///< voxel coordinates of cube min corners, ground axes
    MeshRegion occluder_region;  ///< region + occluder margin (halo_vox = the margin)
    double voxel_size_m = 0;
    int up_axis = 2;          ///< 0 = x, 1 = y, 2 = z
    Box3d core_W;             ///< ground axes: the core; up axis: the map's observed range
    Box3d halo_W;             ///< core grown by the halo
    /// (frame, camera) of every view that may see the tile (frustum, max view distance).
    std::vector<std::pair<std::size_t, std::size_t>> views;

    /// "<ix>_<iy>", the tile's folder name below tiles/.
    std::string name() const { return std::to_string(ix) + "_" + std::to_string(iy); }
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

    /// Tiles holding at least one observed leaf of `map`, views not yet assigned.
    std::vector<Tile> tilesOf(const VoxelMap& map) const;
    /// Assigns to each tile every view of the dataset (frame x camera) whose frustum may see
    /// the tile's halo box within `max_view_distance_m`.
    static void assignViews(std::vector<Tile>& tiles, const Dataset& dataset,
                            double max_view_distance_m);

private:
    Tile makeTile(int ix, int iy, double z_min_m, double z_max_m) const;
    double voxel_size_m_;
    int up_axis_;
    int axes_[2];
    std::int32_t tile_vox_;
    std::int32_t halo_vox_;
    std::int32_t occluder_vox_;
};

}  // namespace vdbmap
