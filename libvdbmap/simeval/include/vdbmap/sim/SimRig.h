// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Camera.h"

namespace vdbmap {

/// One camera of a simulated rig, rigidly mounted on the vehicle.
struct RigCamera {
    std::string name;  ///< "front", "left", "right", "rear": folders image_<name>, semantic_<name>
    CameraIntrinsics intrinsics;                ///< pinhole, no distortion
    Isometry3d T_V_C = Isometry3d::Identity();  ///< camera -> vehicle (x forward, y left, z up)
};

/// Options of the surround rig.
struct SurroundRigOptions {
    int width_px = 1280;
    int height_px = 720;
    double hfov_deg = 100.0;       ///< horizontal field of view of each camera, (0, 170]
    double mount_height_m = 1.6;   ///< optical centres above the vehicle origin (the ground)
    double mount_radius_m = 0.25;  ///< optical centres this far out from the vehicle's z axis
};

/// Four cameras looking front (yaw 0), left (+90 deg), rear (180 deg) and right (-90 deg),
/// level (optical axis horizontal), with square pixels: fx = fy = (width_px / 2) /
/// tan(hfov_deg / 2), principal point at the image centre ((width_px - 1) / 2,
/// (height_px - 1) / 2) in the docs/DATA.md pixel convention. Camera frame C (OpenCV): z along the
/// optical axis, x to the right in the image, y down; the optical centre is at
/// (mount_radius_m cos(yaw), mount_radius_m sin(yaw), mount_height_m) in V. With 4 x 100 deg
/// the neighbouring frusta overlap beyond ~1.6 m from the vehicle. Throws InvalidInput for a
/// non-positive size or a field of view outside (0, 170].
std::vector<RigCamera> surroundRig(const SurroundRigOptions& options = {});

}  // namespace vdbmap
