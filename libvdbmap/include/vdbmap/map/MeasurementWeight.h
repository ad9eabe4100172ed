// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// Incidence weight from the unit ray direction sensor -> point: clamp(-n . dir, floor, 1),
/// the form the integrator's voxel loop uses (it has the direction already).
template <typename Vec, typename Scalar>
inline Scalar incidenceWeightAlongRay(const Vec& normal_W, const Vec& dir_W, Scalar floor) {
    return std::clamp(static_cast<Scalar>(-normal_W.dot(dir_W)), floor, Scalar(1));
}

/// Incidence weight of a measurement (paper Sec. 4.2, w = n . (p_s - p_i)), normalised to the
/// cosine of the incidence angle: n . (p_s - p_i) / |p_s - p_i|, then raised to `floor` so that
/// grazing rays still count a little (a point seen from behind its block's plane gets the
/// floor). `normal_W` must be unit length and oriented towards the sensor; a zero normal
/// (degenerate block) gives 1 (the ray direction is the normal).
/// Returns a value in [floor, 1]; 1 if p_i == p_s.
inline double incidenceWeight(const Vec3d& normal_W, const Vec3d& sensor_W, const Vec3d& point_W,
                              double floor) {
    const Vec3d ray = point_W - sensor_W;
    const double range = ray.norm();
    if (!(range > 0.0) || normal_W.squaredNorm() == 0.0) return 1.0;
    return incidenceWeightAlongRay(normal_W, Vec3d(ray / range), floor);
}

/// Drop-off behind the surface (voxblox style): 1 for sdf >= -voxel_size_m, then linear down
/// to 0 at sdf = -truncation_m, with inv_dropoff = 1 / (truncation_m - voxel_size_m)
/// precomputed (0: no drop-off), the form the voxel loop uses.
template <typename Scalar>
inline Scalar behindSurfaceFactor(Scalar sdf_m, Scalar truncation_m, Scalar voxel_size_m,
                                  Scalar inv_dropoff) {
    if (sdf_m >= -voxel_size_m || !(inv_dropoff > Scalar(0))) return Scalar(1);
    return std::clamp((truncation_m + sdf_m) * inv_dropoff, Scalar(0), Scalar(1));
}

/// behindSurfaceFactor for one voxel; if truncation_m <= voxel_size_m there is no drop-off.
inline double behindSurfaceFactor(double sdf_m, double truncation_m, double voxel_size_m) {
    const double inv = truncation_m > voxel_size_m ? 1.0 / (truncation_m - voxel_size_m) : 0.0;
    return behindSurfaceFactor(sdf_m, truncation_m, voxel_size_m, inv);
}

}  // namespace vdbmap
