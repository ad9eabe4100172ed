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

/// Noise weight of a sample's distance along the normal (adaptive and fixed modes). The range
/// noise sigma_r acts along the ray, so it reaches n . (v - p) scaled by the incidence cosine
/// c = |n . d|, on top of a floor sigma_0 (normal, pose and voxel errors):
///   var = sigma_0^2 (1 + q^2 c^2),  q = sigma_r / sigma_0.
/// Its inverse relative to a frontal sample, (1 + q^2) / (1 + q^2 c^2), lies in [1, 1 + q^2]:
/// a grazing sample's distance across the surface is the more precise one. (The paper's
/// w = n . (p_s - p_i) ranks them the other way round, for the range itself.) q = 0 gives 1.
template <typename Scalar>
inline Scalar noiseWeight(Scalar cos_incidence, Scalar q) {
    const Scalar q2 = q * q;
    return (Scalar(1) + q2) / (Scalar(1) + q2 * cos_incidence * cos_incidence);
}

/// q of noiseWeight for a block whose plane has flatness P_flat (paper Eq. 3): q · P_flat².
/// The variance model holds where the block is a plane; at an edge or a corner of an object
/// (P_flat well below 1) a grazing sample's distance along the block's mixed normal is not the
/// precise one, and its weight tends to a frontal sample's (a box seen from all sides: with the
/// full q its edges were meshed up to 1.4 voxels off, with holes).
template <typename Scalar>
inline Scalar blockNoiseRatio(Scalar q, Scalar flatness) {
    return q * flatness * flatness;
}

/// Trust in a sample at a voxel t metres along the ray from its point (adaptive and fixed
/// modes): the plane through the point is extrapolated over |t|, so the sample counts
/// 1 / (1 + (t / l)^2), at least `floor` (a lone distant sample still completes the surface
/// where nothing nearer was measured). inv_l2 = 1 / l^2; 0 = no falloff (1). `reciprocal(x)`
/// computes 1 / x (the voxel kernel passes an estimate, map/FastReciprocal.h).
template <typename Scalar, typename Reciprocal>
inline Scalar distanceFalloff(Scalar t_m, Scalar inv_l2, Scalar floor, Reciprocal reciprocal) {
    return std::max(floor, reciprocal(Scalar(1) + t_m * t_m * inv_l2));
}

/// distanceFalloff with the exact division.
template <typename Scalar>
inline Scalar distanceFalloff(Scalar t_m, Scalar inv_l2, Scalar floor) {
    return distanceFalloff(t_m, inv_l2, floor, [](Scalar x) { return Scalar(1) / x; });
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
