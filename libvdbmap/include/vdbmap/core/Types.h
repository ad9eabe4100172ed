// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace vdbmap {

using Vec3f = Eigen::Vector3f;
using Vec3d = Eigen::Vector3d;
using Vec2d = Eigen::Vector2d;
using Mat3d = Eigen::Matrix3d;
using Mat4d = Eigen::Matrix4d;
/// Rigid transform. `T_A_B` maps points from frame B into frame A: x_A = T_A_B * x_B.
using Isometry3d = Eigen::Isometry3d;

/// A scan: points in one frame (the name of the variable says which, e.g. `points_L`),
/// with optional per-point intensity (same length as `points` or empty).
struct PointCloud {
    std::vector<Vec3f> points;
    std::vector<float> intensity;

    std::size_t size() const { return points.size(); }
    bool empty() const { return points.empty(); }
};

}  // namespace vdbmap
