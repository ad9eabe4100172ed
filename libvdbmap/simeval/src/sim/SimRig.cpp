// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/sim/SimRig.h"

#include <cmath>

#include "vdbmap/Error.h"

namespace vdbmap {

std::vector<RigCamera> surroundRig(const SurroundRigOptions& options) {
    if (options.width_px <= 0 || options.height_px <= 0 ||
        !(options.hfov_deg > 0.0 && options.hfov_deg <= 170.0)) {
        throw InvalidInput(
            "surroundRig: need a positive image size and hfov_deg in (0, 170], got " +
            std::to_string(options.width_px) + "x" + std::to_string(options.height_px) + " and " +
            std::to_string(options.hfov_deg) + " deg");
    }
    CameraIntrinsics K;
    K.width = options.width_px;
    K.height = options.height_px;
    K.fx = K.fy = 0.5 * options.width_px / std::tan(0.5 * options.hfov_deg * M_PI / 180.0);
    K.cx = 0.5 * (options.width_px - 1);
    K.cy = 0.5 * (options.height_px - 1);
    const std::pair<const char*, double> mounts[] = {
        {"front", 0.0}, {"left", 90.0}, {"rear", 180.0}, {"right", -90.0}};
    std::vector<RigCamera> rig;
    for (const auto& [name, yaw_deg] : mounts) {
        const double yaw = yaw_deg * M_PI / 180.0;
        const Vec3d z_V(std::cos(yaw), std::sin(yaw), 0.0);  // optical axis
        const Vec3d y_V(0.0, 0.0, -1.0);                     // image down
        const Vec3d x_V = y_V.cross(z_V);                    // image right
        RigCamera camera;
        camera.name = name;
        camera.intrinsics = K;
        camera.T_V_C.linear().col(0) = x_V;
        camera.T_V_C.linear().col(1) = y_V;
        camera.T_V_C.linear().col(2) = z_V;
        camera.T_V_C.translation() =
            options.mount_radius_m * z_V + Vec3d(0.0, 0.0, options.mount_height_m);
        rig.push_back(camera);
    }
    return rig;
}

}  // namespace vdbmap
