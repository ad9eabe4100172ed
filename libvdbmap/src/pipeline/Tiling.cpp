// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/Tiling.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "vdbmap/Error.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/core/OptionSpec.h"

namespace vdbmap {
namespace {

constexpr std::int32_t kLeafVoxels = 8;  // TsdfLeaf::DIM

[[noreturn]] void badValue(const std::string& where, const std::string& key, double value,
                           const std::string& rule) {
    std::ostringstream os;
    os << where << ": tiling: option '" << key << "' " << rule << ", got " << value;
    throw ConfigError(os.str());
}

}  // namespace

void TilingConfig::declareOptions(OptionSpec& spec) {
    spec.add("tile_size_m",
             "Edge of the square ground tiles the mesh stages run on (rounded to whole voxel "
             "leaves of 8 voxels); 0 = untiled",
             tile_size_m, 0.0, "m");
    spec.add("halo_m", "Border of neighbouring mesh each tile sees (MRFs, seams) but does not write",
             halo_m, 4.0, "m");
    spec.add("max_view_distance_m",
             "A view is given to a tile only if its frustum meets the tile's box within this "
             "depth (camera z); at least the texture and semantic stages' max_depth_m (40 m), "
             "so that no view that can see a face of the tile is left out",
             max_view_distance_m, 40.0, "m");
    spec.add("occluder_margin_m",
             "Mesh this far around a tile is an occluder in its visibility tests (never written; "
             "0 or less than halo_m = the halo only)",
             occluder_margin_m, 30.0, "m");
    spec.add("merge",
             "Also write the single mesh.ply / textured / semantic outputs of an untiled run "
             "(runs the mesh stages once more on the whole map; skipped above merge_max_faces)",
             merge, false);
    spec.add("merge_max_faces", "Largest mesh (faces over all tiles) merge still writes",
             merge_max_faces, std::int64_t(4000000));
    spec.add("stream",
             "Finish (mesh, texture, label, write, free) each tile as soon as no later scan or "
             "view can change it, while the scans are still read; false = all tiles after the "
             "last scan (same outputs)",
             stream, true);
    spec.add("up_axis",
             "World axis pointing up (tiles cut the other two): auto (the W axis closest to the "
             "LiDAR z axis of the first frame), x, y or z",
             up_axis, std::string("auto"));
    spec.add("max_tiles_in_flight",
             "Finished tiles whose texture, semantic and export stages run at the same time, as "
             "tasks beside the integration (each tile's marching cubes runs on the integrating "
             "thread); 0 = the number of threads. 1 = one after the other. Same outputs",
             max_tiles_in_flight, std::int64_t(0));
    spec.add("memory_budget_gb",
             "Memory the tiles in flight are kept within: a tile starts only while the memory "
             "of the process without tiles plus the estimated peaks of the tiles in flight fit "
             "the budget (one tile always runs); a tile whose estimate alone exceeds it is "
             "worked in pieces (its core cut in halves, each with the same halo; the same "
             "outputs for the same budget); 0 = half of MemAvailable at the start",
             memory_budget_gb, 0.0, "GiB");
    spec.add("split_for_processes",
             "Cut the costliest tiles into pieces (halves of their core, each with the same "
             "halo) until the tiles' estimated work spreads evenly over this many processes: "
             "set it to the MPI ranks when they outnumber the tiles' work; 0 = never. The "
             "outputs depend on this value, not on the number of processes that run",
             split_for_processes, std::int64_t(0));
    spec.add("map_vdb",
             "whole: one map.vdb of the whole map at the end (the map stays in memory until "
             "then); per_tile: tiles/<name>/map.vdb of each tile's core, written as it is "
             "finished, and the leaves no later tile reads leave memory (long drives)",
             map_vdb, std::string("whole"));
}

void TilingConfig::validate(double voxel_size_m, const std::string& where) const {
    if (!std::isfinite(tile_size_m) || tile_size_m < 0.0) {
        badValue(where, "tile_size_m", tile_size_m, "must be finite and >= 0 (0 = untiled)");
    }
    if (!std::isfinite(halo_m) || halo_m < 0.0) {
        badValue(where, "halo_m", halo_m, "must be finite and >= 0");
    }
    if (!std::isfinite(max_view_distance_m) || !(max_view_distance_m > 0.0)) {
        badValue(where, "max_view_distance_m", max_view_distance_m, "must be finite and > 0");
    }
    if (!std::isfinite(occluder_margin_m) || occluder_margin_m < 0.0) {
        badValue(where, "occluder_margin_m", occluder_margin_m, "must be finite and >= 0");
    }
    if (max_tiles_in_flight < 0) {
        badValue(where, "max_tiles_in_flight", static_cast<double>(max_tiles_in_flight),
                 "must be >= 0 (0 = the number of threads)");
    }
    if (!std::isfinite(memory_budget_gb) || memory_budget_gb < 0.0) {
        badValue(where, "memory_budget_gb", memory_budget_gb, "must be finite and >= 0 (0 = auto)");
    }
    if (split_for_processes < 0) {
        badValue(where, "split_for_processes", static_cast<double>(split_for_processes),
                 "must be >= 0 (0 = never cut tiles for balance)");
    }
    if (merge_max_faces < 0) {
        badValue(where, "merge_max_faces", static_cast<double>(merge_max_faces), "must be >= 0");
    }
    if (up_axis != "auto" && up_axis != "x" && up_axis != "y" && up_axis != "z") {
        throw ConfigError(where + ": tiling: option 'up_axis' must be auto, x, y or z, got '" +
                          up_axis + "'");
    }
    if (map_vdb != "whole" && map_vdb != "per_tile") {
        throw ConfigError(where + ": tiling: option 'map_vdb' must be whole or per_tile, got '" +
                          map_vdb + "'");
    }
    if (enabled() && voxel_size_m > 0.0) {
        const double leaf_m = kLeafVoxels * voxel_size_m;
        if (tile_size_m < leaf_m - 1e-9) {
            std::ostringstream rule;
            rule << "must be at least one voxel leaf (8 voxels of " << voxel_size_m
                 << " m = " << leaf_m << " m)";
            badValue(where, "tile_size_m", tile_size_m, rule.str());
        }
    }
}

std::size_t Tile::numFrames() const {
    std::set<std::size_t> frames;
    for (const auto& v : views) frames.insert(v.first);
    return frames.size();
}

int TileGrid::resolveUpAxis(const TilingConfig& config, const Dataset* dataset) {
    if (config.up_axis == "x") return 0;
    if (config.up_axis == "y") return 1;
    if (config.up_axis == "z") return 2;
    if (!dataset || dataset->numFrames() == 0) return 2;
    const Eigen::Vector3d up_W = dataset->frame(0).T_W_L.rotation() * Eigen::Vector3d::UnitZ();
    int axis = 0;
    up_W.cwiseAbs().maxCoeff(&axis);
    return axis;
}

TileGrid::TileGrid(const TilingConfig& config, double voxel_size_m, int up_axis)
    : voxel_size_m_(voxel_size_m), up_axis_(up_axis) {
    axes_[0] = up_axis == 0 ? 1 : 0;
    axes_[1] = up_axis == 2 ? 1 : 2;
    const double leaves = std::round(config.tile_size_m / (kLeafVoxels * voxel_size_m));
    tile_vox_ = kLeafVoxels * std::max<std::int32_t>(1, static_cast<std::int32_t>(leaves));
    halo_vox_ = static_cast<std::int32_t>(std::ceil(config.halo_m / voxel_size_m - 1e-9));
    occluder_vox_ = std::max(halo_vox_, static_cast<std::int32_t>(
                                            std::ceil(config.occluder_margin_m / voxel_size_m - 1e-9)));
}

Tile TileGrid::tile(int ix, int iy) const {
    Tile t;
    t.ix = ix;
    t.iy = iy;
    t.voxel_size_m = voxel_size_m_;
    t.up_axis = up_axis_;
    t.region.axes[0] = axes_[0];
    t.region.axes[1] = axes_[1];
    t.region.core_min[0] = ix * tile_vox_;
    t.region.core_min[1] = iy * tile_vox_;
    t.region.core_max[0] = (ix + 1) * tile_vox_;
    t.region.core_max[1] = (iy + 1) * tile_vox_;
    t.region.halo_vox = halo_vox_;
    t.occluder_region = t.region;
    t.occluder_region.halo_vox = occluder_vox_;
    // A cube with min corner c spans [c, c + 1] voxels, the voxel centres being at c * vs.
    const double vs = voxel_size_m_;
    const double h = halo_vox_ * vs;
    for (int k = 0; k < 2; ++k) {
        t.core_W.min_W[axes_[k]] = t.region.core_min[k] * vs;
        t.core_W.max_W[axes_[k]] = t.region.core_max[k] * vs;
        t.halo_W.min_W[axes_[k]] = t.core_W.min_W[axes_[k]] - h;
        t.halo_W.max_W[axes_[k]] = t.core_W.max_W[axes_[k]] + h;
    }
    return t;
}

bool TileGrid::canSplit(const Tile& t) const {
    for (int k = 0; k < 2; ++k) {
        if (t.region.core_max[k] - t.region.core_min[k] >= 2 * kLeafVoxels) return true;
    }
    return false;
}

std::vector<Tile> TileGrid::split(const Tile& t) const {
    // The cuts along each ground axis: the core's ends, and its middle leaf edge if it holds
    // two leaves or more.
    std::vector<std::int32_t> cuts[2];
    for (int k = 0; k < 2; ++k) {
        const std::int32_t lo = t.region.core_min[k], hi = t.region.core_max[k];
        const std::int32_t leaves = (hi - lo) / kLeafVoxels;
        cuts[k] = leaves >= 2 ? std::vector<std::int32_t>{lo, lo + (leaves / 2) * kLeafVoxels, hi}
                              : std::vector<std::int32_t>{lo, hi};
    }
    std::vector<Tile> pieces;
    const double vs = voxel_size_m_;
    const double h = halo_vox_ * vs;
    for (std::size_t j = 0; j + 1 < cuts[1].size(); ++j) {
        for (std::size_t i = 0; i + 1 < cuts[0].size(); ++i) {
            Tile p;
            p.ix = t.ix;
            p.iy = t.iy;
            p.voxel_size_m = t.voxel_size_m;
            p.up_axis = t.up_axis;
            p.max_view_distance_m = t.max_view_distance_m;
            p.scan_frames = t.scan_frames;
            p.region = t.region;
            p.region.core_min[0] = cuts[0][i];
            p.region.core_max[0] = cuts[0][i + 1];
            p.region.core_min[1] = cuts[1][j];
            p.region.core_max[1] = cuts[1][j + 1];
            p.occluder_region = p.region;
            p.occluder_region.halo_vox = t.occluder_region.halo_vox;
            for (int k = 0; k < 2; ++k) {
                p.core_W.min_W[axes_[k]] = p.region.core_min[k] * vs;
                p.core_W.max_W[axes_[k]] = p.region.core_max[k] * vs;
                p.halo_W.min_W[axes_[k]] = p.core_W.min_W[axes_[k]] - h;
                p.halo_W.max_W[axes_[k]] = p.core_W.max_W[axes_[k]] + h;
            }
            const std::size_t index = j * (cuts[0].size() - 1) + i;
            p.piece = (t.piece.empty() ? "" : t.piece + ".") + std::to_string(index);
            pieces.push_back(std::move(p));
        }
    }
    return pieces;
}

Tile TileGrid::piece(int ix, int iy, const std::string& path) const {
    // A path is one digit per level (split() makes at most 4 pieces), the levels joined by '.'.
    Tile t = tile(ix, iy);
    for (std::size_t at = 0; at < path.size(); at += 2) {
        const std::vector<Tile> pieces = canSplit(t) ? split(t) : std::vector<Tile>();
        const bool digit = path[at] >= '0' && path[at] <= '9';
        const bool joined = at + 1 == path.size() || (path[at + 1] == '.' && at + 2 < path.size());
        const std::size_t index = digit ? static_cast<std::size_t>(path[at] - '0') : pieces.size();
        if (!joined || index >= pieces.size()) {
            throw InvalidInput("tile " + tileName(ix, iy) + ": no piece '" + path + "'");
        }
        t = pieces[index];
    }
    return t;
}

bool TileGrid::fitToMap(Tile& t, const VoxelMap& map) const {
    const MeshRegion& r = t.region;
    std::int32_t up_min = 0, up_max = 0;
    bool any = false, in_core = false;
    for (const TsdfLeafView& leaf : map.leafViews()) {
        const std::int32_t a = leaf.origin[axes_[0]], b = leaf.origin[axes_[1]];
        // Leaves overlapping the halo region [core_min - halo, core_max + halo) on both axes.
        if (a + kLeafVoxels <= r.core_min[0] - r.halo_vox || a >= r.core_max[0] + r.halo_vox ||
            b + kLeafVoxels <= r.core_min[1] - r.halo_vox || b >= r.core_max[1] + r.halo_vox) {
            continue;
        }
        in_core = in_core || r.inCore(a, b);  // tile edges are whole leaves
        const std::int32_t up = leaf.origin[up_axis_];
        up_min = any ? std::min(up_min, up) : up;
        up_max = any ? std::max(up_max, up + kLeafVoxels) : up + kLeafVoxels;
        any = true;
    }
    t.core_W.min_W[up_axis_] = t.halo_W.min_W[up_axis_] = up_min * voxel_size_m_;
    t.core_W.max_W[up_axis_] = t.halo_W.max_W[up_axis_] = up_max * voxel_size_m_;
    return in_core;
}

std::vector<Tile> TileGrid::tilesOf(const VoxelMap& map) const {
    std::set<std::pair<int, int>> keys;  // (iy, ix)
    for (const TsdfLeafView& leaf : map.leafViews()) {
        const auto [ix, iy] = tileOf(leaf.origin);
        keys.insert({iy, ix});
    }
    std::vector<Tile> tiles;
    for (const auto& [iy, ix] : keys) {
        tiles.push_back(tile(ix, iy));
        fitToMap(tiles.back(), map);
    }
    return tiles;
}

void TileGrid::assignViews(std::vector<Tile>& tiles, const Dataset& dataset,
                           double max_view_distance_m) {
    const std::vector<View> views = datasetViews(dataset, false, false);
    for (Tile& tile : tiles) assignViews(tile, views, max_view_distance_m);
}

void TileGrid::assignViews(Tile& tile, const std::vector<View>& views,
                           double max_view_distance_m) {
    tile.views.clear();
    for (const View& view : views) {
        if (viewFrustumMeetsBox(view, tile.halo_W, 0.0, max_view_distance_m)) {
            tile.views.emplace_back(view.frame, view.camera);
        }
    }
}

}  // namespace vdbmap
