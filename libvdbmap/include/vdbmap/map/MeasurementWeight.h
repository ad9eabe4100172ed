// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// Incidence weight of a measurement (paper Sec. 4.2, w = n . (p_s - p_i)), normalised to the
/// cosine of the incidence angle: n . (p_s - p_i) / |p_s - p_i|, then raised to `floor` so that
/// grazing rays still count a little. `normal_W` must be unit length and oriented towards the
/// sensor; a zero normal (degenerate block) gives 1 (the ray direction is the normal).
/// Returns a value in [floor, 1]; 1 if p_i == p_s.
double incidenceWeight(const Vec3d& normal_W, const Vec3d& sensor_W, const Vec3d& point_W,
                       double floor);

/// Drop-off behind the surface (voxblox style): 1 for sdf >= -voxel_size_m, then linear down
/// to 0 at sdf = -truncation_m. If truncation_m <= voxel_size_m there is no drop-off.
double behindSurfaceFactor(double sdf_m, double truncation_m, double voxel_size_m);

}  // namespace vdbmap
