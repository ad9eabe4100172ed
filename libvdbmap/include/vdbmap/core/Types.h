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

/// A read-only view of contiguous points owned by someone else (a std::vector, a numpy array's
/// rows): what the integrator reads without copying the caller's buffer.
class PointSpan {
public:
    PointSpan() = default;
    PointSpan(const Vec3f* points, std::size_t count) : data_(points), size_(count) {}
    PointSpan(const std::vector<Vec3f>& points)  // NOLINT(google-explicit-constructor): on purpose
        : data_(points.data()), size_(points.size()) {}

    const Vec3f* data() const { return data_; }
    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    const Vec3f& operator[](std::size_t i) const { return data_[i]; }
    const Vec3f* begin() const { return data_; }
    const Vec3f* end() const { return data_ + size_; }

private:
    const Vec3f* data_ = nullptr;
    std::size_t size_ = 0;
};
static_assert(sizeof(Vec3f) == 3 * sizeof(float), "PointSpan views (N, 3) float arrays as Vec3f");

}  // namespace vdbmap
