// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/MeasurementWeight.h"

#include <algorithm>

namespace vdbmap {

double incidenceWeight(const Vec3d& normal_W, const Vec3d& sensor_W, const Vec3d& point_W,
                       double floor) {
    const Vec3d ray = sensor_W - point_W;
    const double range = ray.norm();
    if (!(range > 0.0) || normal_W.squaredNorm() == 0.0) return 1.0;
    // Paper Sec. 4.2: w = n . (p_s - p_i), normalised by the range to the cosine of the
    // incidence angle; a point seen from behind its block's plane gets the floor.
    const double cos_incidence = normal_W.dot(ray) / range;
    return std::clamp(cos_incidence, floor, 1.0);
}

double behindSurfaceFactor(double sdf_m, double truncation_m, double voxel_size_m) {
    if (sdf_m >= -voxel_size_m || truncation_m <= voxel_size_m) return 1.0;
    const double f = (truncation_m + sdf_m) / (truncation_m - voxel_size_m);
    return std::clamp(f, 0.0, 1.0);
}

}  // namespace vdbmap
