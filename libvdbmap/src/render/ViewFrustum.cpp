// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/render/ViewFrustum.h"

#include <array>
#include <cmath>

namespace vdbmap {

double viewDistanceToBox(const View& view, const Box3d& box) {
    const Eigen::Vector3d centre_W = view.T_C_W.inverse().translation();
    const Eigen::Vector3d nearest = centre_W.cwiseMax(box.min_W).cwiseMin(box.max_W);
    return (nearest - centre_W).norm();
}

bool viewMaySeeBox(const View& view, const Box3d& box, double min_depth_m, double max_depth_m) {
    if (viewDistanceToBox(view, box) > max_depth_m) return false;
    return viewFrustumMeetsBox(view, box, min_depth_m, max_depth_m);
}

bool viewFrustumMeetsBox(const View& view, const Box3d& box, double min_depth_m,
                         double max_depth_m) {
    std::array<Eigen::Vector3d, 8> corners_C;
    for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d p_W((k & 1) ? box.max_W.x() : box.min_W.x(),
                                  (k & 2) ? box.max_W.y() : box.min_W.y(),
                                  (k & 4) ? box.max_W.z() : box.min_W.z());
        corners_C[static_cast<std::size_t>(k)] = view.T_C_W * p_W;
    }
    // Half-space tests of the pinhole frustum: each plane as a . p_C >= 0 inside
    // (u = fx x/z + cx in [-0.5, w - 0.5] <=> fx x + (cx + 0.5) z >= 0, ...).
    const CameraIntrinsics& k = view.intrinsics;
    const double left = k.cx + 0.5, right = k.width - 0.5 - k.cx;
    const double top = k.cy + 0.5, bottom = k.height - 0.5 - k.cy;
    const std::array<Eigen::Vector4d, 6> planes{
        Eigen::Vector4d(0, 0, 1, -min_depth_m),  // z >= min depth
        Eigen::Vector4d(0, 0, -1, max_depth_m),  // z <= max depth
        Eigen::Vector4d(k.fx, 0, left, 0),       // u >= -0.5
        Eigen::Vector4d(-k.fx, 0, right, 0),     // u <= w - 0.5
        Eigen::Vector4d(0, k.fy, top, 0),        // v >= -0.5
        Eigen::Vector4d(0, -k.fy, bottom, 0)};   // v <= h - 0.5
    for (const Eigen::Vector4d& plane : planes) {
        bool all_outside = true;
        for (const Eigen::Vector3d& p : corners_C) {
            if (plane.head<3>().dot(p) + plane[3] >= 0.0) {
                all_outside = false;
                break;
            }
        }
        if (all_outside) return false;
    }
    return true;
}

}  // namespace vdbmap
