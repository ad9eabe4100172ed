// SPDX-License-Identifier: Apache-2.0
#include "pipeline/PointRegion.h"

#include <algorithm>

#include "vdbmap/pipeline/TilePlan.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap::detail {

PointRegion::PointRegion(const TileGrid& grid, const TilePlan& plan, int process,
                         double update_reach_m) {
    axis_[0] = grid.groundAxis(0);
    axis_[1] = grid.groundAxis(1);
    const double size_m = grid.tileSizeM();
    // What a tile needs integrated (TilePlan: the occluder region and the voxel a cube reaches
    // past its min corner), the update reach, and one leaf more against rounding.
    const double needed_m = (grid.occluderVoxels() + 1) * grid.voxelSize();
    const double grow_m = needed_m + update_reach_m + 8.0 * grid.voxelSize();
    for (const PlannedTile& t : plan.tiles) {
        if (t.process != process) continue;
        const Rect r{static_cast<float>(t.ix * size_m - grow_m), static_cast<float>(t.iy * size_m - grow_m),
                     static_cast<float>((t.ix + 1) * size_m + grow_m),
                     static_cast<float>((t.iy + 1) * size_m + grow_m)};
        if (rects_.empty()) {
            bound_ = r;
        } else {
            bound_ = {std::min(bound_[0], r[0]), std::min(bound_[1], r[1]), std::max(bound_[2], r[2]),
                      std::max(bound_[3], r[3])};
        }
        rects_.push_back(r);
    }
}

bool PointRegion::contains(const Vec3f& p_W) const {
    const float g0 = p_W[axis_[0]], g1 = p_W[axis_[1]];
    if (!inside(bound_, g0, g1)) return false;
    return std::any_of(rects_.begin(), rects_.end(), [&](const Rect& r) { return inside(r, g0, g1); });
}

}  // namespace vdbmap::detail
