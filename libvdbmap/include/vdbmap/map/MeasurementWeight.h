// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// Incidence weight of a measurement (paper Sec. 4.2, w = n . (p_s - p_i)), normalised to the
/// cosine of the incidence angle: n . (p_s - p_i) / |p_s - p_i|, then raised to `floor` so that
/// grazing rays still count a little. `normal_W` must be unit length and oriented towards the
/// sensor; a zero normal (degenerate block) gives 1 (the ray direction is the normal).
/// Returns a value in [floor, 1]; 1 if p_i == p_s. Inline: it runs once per point.
inline double incidenceWeight(const Vec3d& normal_W, const Vec3d& sensor_W, const Vec3d& point_W,
                              double floor) {
    const Vec3d ray = sensor_W - point_W;
    const double range = ray.norm();
    if (!(range > 0.0) || normal_W.squaredNorm() == 0.0) return 1.0;
    // A point seen from behind its block's plane gets the floor.
    const double cos_incidence = normal_W.dot(ray) / range;
    return std::clamp(cos_incidence, floor, 1.0);
}

/// Drop-off behind the surface (voxblox style): 1 for sdf >= -voxel_size_m, then linear down
/// to 0 at sdf = -truncation_m. If truncation_m <= voxel_size_m there is no drop-off.
/// Inline: it runs once per voxel update.
inline double behindSurfaceFactor(double sdf_m, double truncation_m, double voxel_size_m) {
    if (sdf_m >= -voxel_size_m || truncation_m <= voxel_size_m) return 1.0;
    const double f = (truncation_m + sdf_m) / (truncation_m - voxel_size_m);
    return std::clamp(f, 0.0, 1.0);
}

}  // namespace vdbmap
