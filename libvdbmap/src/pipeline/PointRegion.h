// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

class TileGrid;
struct TilePlan;

namespace detail {

/// The ground a process's points must fall in to matter (issue 37): the union of its tiles'
/// occluder regions (core grown by the occluder margin and one voxel, what a tile needs
/// integrated) grown by the integrator's update reach. A point outside changes no voxel any of
/// those tiles reads, so a rank of a distributed run drops it before integrating (its tiles,
/// and its part of map.vdb, stay those of the single-process run: MpiRunTest).
///
/// Why the reach suffices: a voxel is changed only by points within maxUpdateReach of it, and
/// such a point reads the statistics of its block's 26 neighbours (points within 2 leaves per
/// axis); the stage's update reach is maxUpdateReach plus 4 leaves, and the test is per ground
/// axis (a square, not a disc), so every point that can reach a tile's region is inside.
class PointRegion {
public:
    /// The region of the tiles of `plan` run by `process`, on the ground axes of `grid`.
    PointRegion(const TileGrid& grid, const TilePlan& plan, int process, double update_reach_m);

    /// Whether the W point p_W lies in the region (its coordinate along the up axis is free).
    bool contains(const Vec3f& p_W) const;
    /// Rectangles of the region (one per tile of the process).
    std::size_t rectangles() const { return rects_.size(); }

private:
    using Rect = std::array<float, 4>;  ///< min0, min1, max0, max1 on the ground axes, metres
    static bool inside(const Rect& r, float g0, float g1) {
        return g0 >= r[0] && g1 >= r[1] && g0 <= r[2] && g1 <= r[3];
    }
    int axis_[2] = {0, 1};
    std::vector<Rect> rects_;
    Rect bound_{1.f, 1.f, -1.f, -1.f};  ///< of every rectangle (empty: no tile)
};

}  // namespace detail
}  // namespace vdbmap
