// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <string>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// Pinhole intrinsics with optional radial-tangential (OpenCV "plumb bob") distortion.
/// Pixel convention (docs/DATA.md): (0,0) is the centre of the top-left pixel.
struct CameraIntrinsics {
    int width = 0;                          ///< px
    int height = 0;                         ///< px
    double fx = 0, fy = 0, cx = 0, cy = 0;  ///< focal lengths and principal point, px
    /// k1 k2 p1 p2 k3; all zero = no distortion (rectified KITTI).
    std::array<double, 5> distortion{0, 0, 0, 0, 0};

    /// True if any distortion coefficient is non-zero.
    bool hasDistortion() const;
    /// Projects a point in the camera frame C (z forward) to a pixel (OpenCV model). Returns
    /// false, with `pixel` set to NaN, if z <= 0 (or z is NaN). Does not check inside().
    bool project(const Vec3d& p_C, Vec2d& pixel) const;
    /// True if the pixel lies inside [-0.5, width-0.5) x [-0.5, height-0.5).
    bool inside(const Vec2d& pixel) const {
        return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() < width - 0.5 &&
               pixel.y() < height - 0.5;
    }
};

/// One camera of a sequence, rigidly mounted on the LiDAR.
struct Camera {
    std::string name;           ///< image folder, e.g. "image_2"
    std::string semantic_name;  ///< semantic folder, e.g. "semantic_2" ("" = none)
    CameraIntrinsics intrinsics;
    Isometry3d T_C_L = Isometry3d::Identity();  ///< LiDAR frame -> camera frame
};

}  // namespace vdbmap
