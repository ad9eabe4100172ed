// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/TilePlan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>

#include "vdbmap/Error.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/render/ViewFrustum.h"

namespace vdbmap {
namespace {

constexpr double kCostSigmaM = 20.0;  // a frame's coverage of a tile falls off with its distance
// Cutting for balance (cutForBalance): stop once the largest process share is within this
// factor of the even share; never cut a tile below this part of the even share.
constexpr double kBalanceSlack = 1.1;
constexpr double kLeastCutShare = 0.5;
// A cut is kept only if its costliest piece has at most this share of the tile's cost.
constexpr double kLeastGrainGain = 0.8;
// A piece's share of its tile's cost: its weighted frames with this steeper falloff. A tile's
// work is where its faces are, near the drive; the frames' 20 m falloff gave the pieces
// behind the buildings (no observed leaf, no work) a fifth of a street tile's cost (measured:
// docs/benchmarks/scale.md, "Tiles cut for balance").
constexpr double kPieceShareSigmaM = 10.0;

/// A rectangle on the two ground axes, metres.
struct GroundRect {
    double min[2], max[2];
    GroundRect grown(double m) const { return {{min[0] - m, min[1] - m}, {max[0] + m, max[1] + m}}; }
    double distance(const double p[2]) const {
        double d2 = 0.0;
        for (int k = 0; k < 2; ++k) {
            const double d = std::max({min[k] - p[k], 0.0, p[k] - max[k]});
            d2 += d * d;
        }
        return std::sqrt(d2);
    }
};

using TileKey = std::pair<int, int>;  // (iy, ix)

/// How far from the camera centre a point of the view's frustum at depth <= depth_m can lie:
/// depth times the length of the ray through the farthest image corner (z = 1).
double frustumReach(const View& view, double depth_m) {
    const CameraIntrinsics& k = view.intrinsics;
    const double x = std::max(k.cx + 0.5, k.width - 0.5 - k.cx) / k.fx;
    const double y = std::max(k.cy + 0.5, k.height - 0.5 - k.cy) / k.fy;
    return depth_m * std::sqrt(1.0 + x * x + y * y);
}

class Planner {
public:
    Planner(const TileGrid& grid, const Dataset& dataset, const TilePlanOptions& options)
        : grid_(grid), dataset_(dataset), options_(options), size_m_(grid.tileSizeM()),
          // The occluder region plus the voxel a cube reaches past its min corner.
          needed_m_((grid.occluderVoxels() + 1) * grid.voxelSize()) {}

    TilePlan plan() {
        scanPhase();
        viewPhase();
        return assignPhase();
    }

private:
    GroundRect core(int ix, int iy) const {
        return {{ix * size_m_, iy * size_m_}, {(ix + 1) * size_m_, (iy + 1) * size_m_}};
    }

    void ground(const Eigen::Vector3d& p_W, double g[2]) const {
        g[0] = p_W[grid_.groundAxis(0)];
        g[1] = p_W[grid_.groundAxis(1)];
    }

    /// Calls visit(ix, iy) for every tile whose rectangle grown by `margin_m` may lie within
    /// `radius_m` of the ground point g.
    template <typename Visit>
    void tilesAround(const double g[2], double radius_m, double margin_m, Visit&& visit) const {
        const double r = radius_m + margin_m;
        const int x0 = static_cast<int>(std::floor((g[0] - r) / size_m_));
        const int x1 = static_cast<int>(std::floor((g[0] + r) / size_m_));
        const int y0 = static_cast<int>(std::floor((g[1] - r) / size_m_));
        const int y1 = static_cast<int>(std::floor((g[1] + r) / size_m_));
        for (int iy = y0; iy <= y1; ++iy)
            for (int ix = x0; ix <= x1; ++ix) visit(ix, iy);
    }

    /// Phase 1: the tiles a scan can reach (their core: they may hold leaves) and, for each,
    /// the frames that reach its occluder region; the cost estimate; the up range of the poses.
    void scanPhase() {
        const double reach = options_.scan_reach_m;
        for (std::size_t i = 0; i < dataset_.numFrames(); ++i) {
            const Eigen::Vector3d o_W = dataset_.frame(i).T_W_L.translation();
            const double up = o_W[grid_.upAxis()];
            up_min_ = std::min(up_min_, up);
            up_max_ = std::max(up_max_, up);
            double g[2];
            ground(o_W, g);
            frame_ground_.push_back({g[0], g[1]});
            tilesAround(g, reach, needed_m_, [&](int ix, int iy) {
                const GroundRect c = core(ix, iy);
                if (c.grown(needed_m_).distance(g) > reach) return;
                // Tiles exist only where a scan reaches their core; the frames that reach
                // only their margin are recorded in case a nearer frame creates them.
                PlannedTile& t = tiles_[{iy, ix}];
                t.ix = ix;
                t.iy = iy;
                t.scan_frames.push_back(i);
                const double d = c.distance(g);
                t.weighted_frames += std::exp(-d * d / (2.0 * kCostSigmaM * kCostSigmaM));
                if (d <= reach) reached_core_[{iy, ix}] = true;
            });
        }
        for (auto it = tiles_.begin(); it != tiles_.end();) {
            it = reached_core_.count(it->first) ? std::next(it) : tiles_.erase(it);
        }
        for (auto& [key, t] : tiles_) t.finish_frame = t.scan_frames.back();
    }

    /// Phase 2: the views that may see each tile (its frustum up to the max view depth against
    /// the tile's halo box, spanning every height a scan can reach: the tile's real box, known
    /// once its leaves are, lies inside, so the views it gets are among these): their number,
    /// and the last one, after which the tile can be finished. Then the tiles' cost estimates.
    void viewPhase() {
        if (tiles_.empty()) return;
        const double halo_m = grid_.haloM();
        const double reach = options_.scan_reach_m;
        for (const View& view : datasetViews(dataset_, false, false)) {
            const Eigen::Vector3d c_W = view.T_C_W.inverse().translation();
            double g[2];
            ground(c_W, g);
            tilesAround(g, frustumReach(view, options_.max_view_distance_m), halo_m,
                        [&](int ix, int iy) {
                auto it = tiles_.find({iy, ix});
                if (it == tiles_.end()) return;
                const GroundRect h = core(ix, iy).grown(halo_m);
                Box3d box;
                box.min_W[grid_.groundAxis(0)] = h.min[0];
                box.min_W[grid_.groundAxis(1)] = h.min[1];
                box.max_W[grid_.groundAxis(0)] = h.max[0];
                box.max_W[grid_.groundAxis(1)] = h.max[1];
                box.min_W[grid_.upAxis()] = up_min_ - reach;
                box.max_W[grid_.upAxis()] = up_max_ + reach;
                if (viewFrustumMeetsBox(view, box, 0.0, options_.max_view_distance_m)) {
                    PlannedTile& t = it->second;
                    ++t.views;
                    t.finish_frame = std::max(t.finish_frame, view.frame);
                }
            });
        }
        for (auto& [key, t] : tiles_) t.cost = tileCostEstimate(t.weighted_frames, t.views);
    }

    /// Phase 3: finish order, processes.
    TilePlan assignPhase() {
        TilePlan plan;
        const std::size_t last = dataset_.numFrames() == 0 ? 0 : dataset_.numFrames() - 1;
        for (auto& [key, t] : tiles_) {
            if (!options_.stream) t.finish_frame = last;
            plan.tiles.push_back(std::move(t));
        }
        std::sort(plan.tiles.begin(), plan.tiles.end(),
                  [](const PlannedTile& a, const PlannedTile& b) {
                      return std::tie(a.finish_frame, a.iy, a.ix) <
                             std::tie(b.finish_frame, b.iy, b.ix);
                  });
        if (options_.split_for_processes > 1) cutForBalance(plan.tiles);
        std::vector<double> costs;
        for (const PlannedTile& t : plan.tiles) costs.push_back(t.cost);
        const std::vector<int> parts = partitionContiguous(costs, options_.processes);
        for (std::size_t i = 0; i < plan.tiles.size(); ++i) plan.tiles[i].process = parts[i];
        return plan;
    }

    /// Phase 3a (issue 37): when the tiles are too few or too uneven for an even split over
    /// split_for_processes, the costliest tile is cut into TileGrid::split's pieces (the pieces
    /// a memory split makes, each with its own halo), one tile at a time, until the best
    /// contiguous split's largest share is within kBalanceSlack of the even share, or no tile
    /// is worth cutting: one below kLeastCutShare of the even share (its halo and views would
    /// cost more than the balance gains), or one whose work would stay in one piece
    /// (kLeastGrainGain). Pieces are not cut again. They take the tile's place in the finish
    /// order; each gets the tile's cost in proportion to the frames near its own core.
    void cutForBalance(std::vector<PlannedTile>& units) const {
        const int n = options_.split_for_processes;
        double total = 0.0;
        for (const PlannedTile& u : units) total += u.cost;
        const double share = total / n;
        std::vector<char> settled(units.size(), 0);  // a piece, or a tile not worth cutting
        while (!units.empty() && largestShare(units, n) > kBalanceSlack * share) {
            std::size_t cut = units.size();
            for (std::size_t i = 0; i < units.size(); ++i) {
                const bool can = !settled[i] && units[i].cost > kLeastCutShare * share;
                if (can && (cut == units.size() || units[i].cost > units[cut].cost)) cut = i;
            }
            if (cut == units.size()) break;  // nothing left worth cutting
            const std::vector<PlannedTile> pieces = piecesOf(units[cut]);
            double coarsest = 0.0;
            for (const PlannedTile& q : pieces) coarsest = std::max(coarsest, q.cost);
            if (pieces.empty() || coarsest > kLeastGrainGain * units[cut].cost) {
                settled[cut] = 1;  // cannot be cut, or its work stays in one piece
                continue;
            }
            const auto at = static_cast<std::ptrdiff_t>(cut);
            units.erase(units.begin() + at);
            settled.erase(settled.begin() + at);
            units.insert(units.begin() + at, pieces.begin(), pieces.end());
            settled.insert(settled.begin() + at, pieces.size(), 1);
        }
    }

    /// The largest process's cost when `units` are split contiguously over n processes.
    static double largestShare(const std::vector<PlannedTile>& units, int n) {
        std::vector<double> costs;
        for (const PlannedTile& u : units) costs.push_back(u.cost);
        const std::vector<int> parts = partitionContiguous(costs, n);
        std::vector<double> sums(static_cast<std::size_t>(n), 0.0);
        for (std::size_t i = 0; i < costs.size(); ++i) sums[static_cast<std::size_t>(parts[i])] += costs[i];
        return *std::max_element(sums.begin(), sums.end());
    }

    /// The pieces of the whole tile `unit` (none if it cannot be cut), its cost shared by the
    /// frames near each piece's core (falling off with kPieceShareSigmaM).
    std::vector<PlannedTile> piecesOf(const PlannedTile& unit) const {
        const Tile whole = grid_.tile(unit.ix, unit.iy);
        if (!grid_.canSplit(whole)) return {};
        std::vector<PlannedTile> pieces;
        std::vector<double> share_weights;
        double weights = 0.0;
        for (const Tile& p : grid_.split(whole)) {
            PlannedTile q = unit;
            q.piece = p.piece;
            q.weighted_frames = weightedFrames(p, q.scan_frames, kCostSigmaM);
            share_weights.push_back(weightedFrames(p, q.scan_frames, kPieceShareSigmaM));
            weights += share_weights.back();
            pieces.push_back(std::move(q));
        }
        for (std::size_t k = 0; k < pieces.size(); ++k) {
            pieces[k].cost = weights > 0.0 ? unit.cost * share_weights[k] / weights
                                           : unit.cost / static_cast<double>(pieces.size());
        }
        return pieces;
    }

    /// Phase 1's coverage weight of `frames` for a piece's core, falling off with `sigma_m`.
    double weightedFrames(const Tile& piece, const std::vector<std::size_t>& frames, double sigma_m) const {
        const GroundRect c{{piece.core_W.min_W[grid_.groundAxis(0)], piece.core_W.min_W[grid_.groundAxis(1)]},
                           {piece.core_W.max_W[grid_.groundAxis(0)], piece.core_W.max_W[grid_.groundAxis(1)]}};
        double w = 0.0;
        for (std::size_t f : frames) {
            const double d = c.distance(frame_ground_[f].data());
            w += std::exp(-d * d / (2.0 * sigma_m * sigma_m));
        }
        return w;
    }

    const TileGrid& grid_;
    const Dataset& dataset_;
    const TilePlanOptions& options_;
    const double size_m_;
    const double needed_m_;
    double up_min_ = std::numeric_limits<double>::max();
    double up_max_ = std::numeric_limits<double>::lowest();
    std::map<TileKey, PlannedTile> tiles_;
    std::map<TileKey, bool> reached_core_;
    std::vector<std::array<double, 2>> frame_ground_;  ///< each frame's sensor on the ground axes
};

}  // namespace

std::vector<std::size_t> TilePlan::framesOf(int process) const {
    std::vector<std::size_t> frames;
    for (const PlannedTile& t : tiles) {
        if (t.process == process) frames.insert(frames.end(), t.scan_frames.begin(), t.scan_frames.end());
    }
    std::sort(frames.begin(), frames.end());
    frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
    return frames;
}

std::size_t TilePlan::tilesOf(int process) const {
    return static_cast<std::size_t>(std::count_if(
        tiles.begin(), tiles.end(), [&](const PlannedTile& t) { return t.process == process; }));
}

const PlannedTile* TilePlan::find(int ix, int iy) const {
    for (const PlannedTile& t : tiles)
        if (t.ix == ix && t.iy == iy) return &t;
    return nullptr;
}

std::size_t TilePlan::pieces() const {
    return static_cast<std::size_t>(std::count_if(
        tiles.begin(), tiles.end(), [](const PlannedTile& t) { return !t.piece.empty(); }));
}

double tileCostEstimate(double weighted_frames, std::size_t views) {
    // Least squares on the 16 tiles of the 400 m street at 0.10 m (config/street_tiled.yaml,
    // one thread, tiles one at a time: each tile's cpu_time_s is its own; 2.1 to 23.3 s):
    // |error| summed 13 % of their CPU, largest 3.6 s (bench/mpi_split_calibrate.py,
    // docs/benchmarks/scale.md). What is left is the scene: of two tiles with the same poses
    // around them, the one with the buildings has 1.3 times the faces and the CPU. A tile with
    // hardly a frame near it (often no face at all) costs next to nothing, not less.
    constexpr double kFixedS = -2.48;
    constexpr double kPerWeightedFrameS = 0.143;
    constexpr double kPerViewS = 0.054;
    constexpr double kLeastS = 0.1;
    return std::max(kLeastS, kFixedS + kPerWeightedFrameS * weighted_frames +
                                 kPerViewS * static_cast<double>(views));
}

std::vector<int> partitionContiguous(const std::vector<double>& costs, int parts) {
    if (parts < 1) throw InvalidInput("partitionContiguous: parts must be >= 1, got " + std::to_string(parts));
    const std::size_t n = costs.size();
    // Greedy fill up to `capacity`, but never leave a later part without an item while items
    // remain for it (idle processes help nobody); returns the parts used or -1 if infeasible.
    auto cut = [&](double capacity, std::vector<int>* out) {
        int part = 0;
        double sum = 0.0;
        bool empty = true;
        for (std::size_t i = 0; i < n; ++i) {
            const bool spread = static_cast<int>(n - i) <= parts - 1 - part;
            if (!empty && (sum + costs[i] > capacity || spread)) {
                ++part;
                sum = 0.0;
            }
            if (part >= parts) return -1;
            sum += costs[i];
            empty = false;
            if (out) (*out)[i] = part;
        }
        return part + 1;
    };
    std::vector<int> out(n, 0);
    if (n == 0) return out;
    double lo = *std::max_element(costs.begin(), costs.end());
    double hi = std::accumulate(costs.begin(), costs.end(), 0.0);
    for (int iter = 0; iter < 100 && hi - lo > 1e-9 * std::max(1.0, hi); ++iter) {
        const double mid = 0.5 * (lo + hi);
        (cut(mid, nullptr) > 0 ? hi : lo) = mid;
    }
    cut(hi, &out);
    return out;
}

TilePlan planTiles(const TileGrid& grid, const Dataset& dataset, const TilePlanOptions& options) {
    if (!std::isfinite(options.scan_reach_m) || options.scan_reach_m < 0.0) {
        throw InvalidInput("planTiles: scan_reach_m must be finite and >= 0, got " +
                           std::to_string(options.scan_reach_m));
    }
    if (options.processes < 1) {
        throw InvalidInput("planTiles: processes must be >= 1, got " +
                           std::to_string(options.processes));
    }
    return Planner(grid, dataset, options).plan();
}

}  // namespace vdbmap
