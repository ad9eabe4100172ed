// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Core>

#include "vdbmap/render/Visibility.h"

namespace vdbmap {

/// An axis-aligned box in the world frame W, metres.
struct Box3d {
    Eigen::Vector3d min_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d max_W = Eigen::Vector3d::Zero();
};

/// Distance from the view's camera centre to the nearest point of `box` (0 inside), metres.
double viewDistanceToBox(const View& view, const Box3d& box);

/// Conservative frustum test: false only if the box lies entirely outside one plane of the
/// view's frustum (image borders, depth in [min_depth_m, max_depth_m]), or farther than
/// max_depth_m from the camera centre. A box that may be seen is never rejected.
bool viewMaySeeBox(const View& view, const Box3d& box, double min_depth_m, double max_depth_m);

/// The frustum planes only: false only if the box lies entirely outside one plane (image
/// borders, camera depth z in [min_depth_m, max_depth_m]). Never rejects a box holding a point
/// that computeVisibility with the same depth limits could find visible.
bool viewFrustumMeetsBox(const View& view, const Box3d& box, double min_depth_m,
                         double max_depth_m);

}  // namespace vdbmap
