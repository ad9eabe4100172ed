// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/math/Coord.h>

#include <cmath>
#include <limits>

#include "vdbmap/core/Types.h"

namespace vdbmap::detail {

/// Amanatides-Woo traversal of the voxels pierced by the segment start_W + t * dir_W,
/// t in [0, length_m] (dir_W unit length). Calls visit(const openvdb::Coord&) in order along
/// the ray. Deterministic; no allocation.
template <typename Visit>
inline void traverseSegment(const Vec3d& start_W, const Vec3d& dir_W, double length_m,
                            double inv_voxel_size, Visit&& visit) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const Vec3d a = start_W * inv_voxel_size + Vec3d::Constant(0.5);  // index space, cell [i, i+1)
    const double length = length_m * inv_voxel_size;
    int ijk[3];
    int step[3];
    double t_max[3];
    double t_delta[3];
    for (int k = 0; k < 3; ++k) {
        const double fl = std::floor(a[k]);
        ijk[k] = static_cast<int>(fl);
        const double d = dir_W[k];
        if (d > 0.0) {
            step[k] = 1;
            t_delta[k] = 1.0 / d;
            t_max[k] = (fl + 1.0 - a[k]) * t_delta[k];
        } else if (d < 0.0) {
            step[k] = -1;
            t_delta[k] = -1.0 / d;
            t_max[k] = (a[k] - fl) * t_delta[k];
        } else {
            step[k] = 0;
            t_delta[k] = kInf;
            t_max[k] = kInf;
        }
    }
    // A segment of length L crosses at most L * sqrt(3) + 3 voxel faces.
    const int max_steps = static_cast<int>(length * 1.7320508 + 4.0);
    for (int s = 0; s < max_steps; ++s) {
        visit(openvdb::Coord(ijk[0], ijk[1], ijk[2]));
        const int axis = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2)
                                             : (t_max[1] < t_max[2] ? 1 : 2);
        if (t_max[axis] > length) break;
        ijk[axis] += step[axis];
        t_max[axis] += t_delta[axis];
    }
}

}  // namespace vdbmap::detail
