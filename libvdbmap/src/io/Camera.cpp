// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/Camera.h"

#include <limits>

namespace vdbmap {

bool CameraIntrinsics::hasDistortion() const {
    for (const double d : distortion) {
        if (d != 0.0) return true;
    }
    return false;
}

bool CameraIntrinsics::project(const Vec3d& p_C, Vec2d& pixel) const {
    if (!(p_C.z() > 0.0)) {
        pixel = Vec2d::Constant(std::numeric_limits<double>::quiet_NaN());
        return false;
    }
    double x = p_C.x() / p_C.z();
    double y = p_C.y() / p_C.z();
    if (hasDistortion()) {
        // OpenCV radial-tangential ("plumb bob") model, the one cv::projectPoints uses with
        // D = (k1, k2, p1, p2, k3).
        const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3],
                     k3 = distortion[4];
        const double r2 = x * x + y * y;
        const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
        const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
        const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
        x = xd;
        y = yd;
    }
    // (0,0) is the centre of the top-left pixel (docs/DATA.md), as in OpenCV.
    pixel = Vec2d(fx * x + cx, fy * y + cy);
    return true;
}

}  // namespace vdbmap
