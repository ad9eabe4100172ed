// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <vector>

#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap {

class Dataset;

/// What a tile plan needs besides the grid and the poses.
struct TilePlanOptions {
    /// How far from its sensor one scan can change the map, metres: the dataset's max_range_m
    /// (farther points are dropped) plus the integrator's update reach (truncation band, the
    /// block statistics a point reads). Must be finite and >= 0.
    double scan_reach_m = 0.0;
    double max_view_distance_m = 40.0;  ///< TilingConfig::max_view_distance_m
    int processes = 1;                  ///< processes (MPI ranks) to spread the tiles over, >= 1
    /// Cut the costliest tiles into pieces until the tiles' work spreads evenly over this many
    /// processes (TilingConfig::split_for_processes); <= 1: no tile is cut for balance. Only
    /// this number, never `processes`, decides the pieces, so that runs on any number of
    /// processes with the same value write the same outputs.
    int split_for_processes = 1;
    /// false: every tile is finished after the last frame (TilingConfig::stream).
    bool stream = true;
};

/// A tile that may exist, planned from the poses alone, before any scan is read.
struct PlannedTile {
    int ix = 0, iy = 0;
    /// A piece of tile (ix, iy) cut for balance (TileGrid::split's path, "2" or "2.0"); "" for
    /// the whole tile. A piece has its tile's scan_frames and finish_frame.
    std::string piece;
    /// Frames whose scans may change the map within the tile's occluder region (the tile grown
    /// by max(halo, occluder margin) and one voxel), ascending: what the tile needs integrated.
    std::vector<std::size_t> scan_frames;
    /// The last frame whose scan or views may change the tile's outputs: the tile can be
    /// finished once this frame is integrated.
    std::size_t finish_frame = 0;
    /// The frames near the tile, each weighted by exp(-d^2 / 2 (20 m)^2) of its sensor's
    /// ground distance d to the tile's core: how much of the tile the scans covered.
    double weighted_frames = 0.0;
    /// The views whose frustum meets the tile's halo box within max_view_distance_m (at every
    /// height a scan reaches): those the tile's texture and semantic stages will project.
    std::size_t views = 0;
    /// Estimated CPU seconds of the tile's stages, for load balance (tileCostEstimate of
    /// weighted_frames and views).
    double cost = 0.0;
    int process = 0;  ///< the process (MPI rank) that runs it

    /// Tile::name(): "<ix>_<iy>" or "<ix>_<iy>.<piece>".
    std::string name() const { return tileName(ix, iy, piece); }
};

/// The pose-based plan of a tiled run (issue 13): every tile a scan can reach (those that
/// will hold observed leaves are among them; the others are dropped when they are finished),
/// the frames each one needs, when it can be finished, and which process runs it.
struct TilePlan {
    /// Sorted by (finish_frame, iy, ix), the order a stream finishes them in.
    std::vector<PlannedTile> tiles;
    /// Frames process `process` must integrate: the union of its tiles' scan_frames, ascending.
    std::vector<std::size_t> framesOf(int process) const;
    /// Number of tiles of process `process`.
    std::size_t tilesOf(int process) const;
    /// The planned tile (ix, iy), or its first piece (the pieces of a tile are consecutive and
    /// the first one's process owns the tile's leaves of map.vdb), or nullptr.
    const PlannedTile* find(int ix, int iy) const;
    /// Pieces cut for balance (split_for_processes).
    std::size_t pieces() const;
};

/// Plans the tiles of `grid` for the frames and views of `dataset`. Tiles are given to the
/// processes as contiguous runs of the finish order (neighbouring tiles share scans, so each
/// process reads a stretch of the drive), cut so that the largest total cost is smallest.
/// With split_for_processes > 1 the costliest tiles are first cut into pieces (cutForBalance in
/// TilePlan.cpp). Deterministic: every process computes the same plan. Throws InvalidInput for
/// a negative or non-finite reach or processes < 1.
TilePlan planTiles(const TileGrid& grid, const Dataset& dataset, const TilePlanOptions& options);

/// The estimated CPU seconds of a tile's stages (marching cubes, texture, semantic, export)
/// from its pose-based features, calibrated on measured per-tile CPU times (street drives at
/// 0.10 m, docs/benchmarks/scale.md). Only its proportions matter to the split.
double tileCostEstimate(double weighted_frames, std::size_t views);

/// Cuts `costs` (in order) into `parts` contiguous runs minimising the largest run's sum;
/// returns the part of each item (non-decreasing, parts may stay empty). parts >= 1.
std::vector<int> partitionContiguous(const std::vector<double>& costs, int parts);

}  // namespace vdbmap
