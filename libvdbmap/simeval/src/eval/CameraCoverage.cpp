// SPDX-License-Identifier: Apache-2.0
// Which ground-truth surface points any input camera saw (scoring on the camera-seen area).
#include "vdbmap/eval/CameraCoverage.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

namespace {

void checkCoverageInputs(const std::vector<Vec3f>& points_W, const std::vector<Vec3f>& normals_W,
                         const std::vector<View>& views, const CoverageOptions& options) {
    if (points_W.size() != normals_W.size()) {
        throw InvalidInput("pointsSeenByViews: " + std::to_string(points_W.size()) +
                           " points but " + std::to_string(normals_W.size()) + " normals");
    }
    if (!(options.max_view_angle_deg > 0.0 && options.max_view_angle_deg <= 90.0) ||
        !(options.min_depth_m >= 0.0) || !(options.max_depth_m > options.min_depth_m) ||
        !(options.occlusion_tolerance_m >= 0.0)) {
        throw InvalidInput("pointsSeenByViews: bad options (max_view_angle_deg " +
                           std::to_string(options.max_view_angle_deg) + ", min_depth_m " +
                           std::to_string(options.min_depth_m) + ", max_depth_m " +
                           std::to_string(options.max_depth_m) + ", occlusion_tolerance_m " +
                           std::to_string(options.occlusion_tolerance_m) + ")");
    }
    for (std::size_t v = 0; v < views.size(); ++v) {
        const CameraIntrinsics& K = views[v].intrinsics;
        if (K.width <= 0 || K.height <= 0 || !(K.fx > 0.0) || !(K.fy > 0.0)) {
            throw InvalidInput("pointsSeenByViews: view " + std::to_string(v) + " has image " +
                               std::to_string(K.width) + "x" + std::to_string(K.height) +
                               " and focal lengths " + std::to_string(K.fx) + ", " +
                               std::to_string(K.fy));
        }
    }
}

}  // namespace

std::vector<std::uint8_t> pointsSeenByViews(const std::vector<Vec3f>& points_W,
                                            const std::vector<Vec3f>& normals_W,
                                            const std::vector<View>& views,
                                            const Raycaster& occluder,
                                            const CoverageOptions& options) {
    checkCoverageInputs(points_W, normals_W, views, options);
    std::vector<Vec3d> centres_W;
    for (const View& v : views) centres_W.push_back(v.T_C_W.inverse().translation());
    const double min_cos = std::cos(options.max_view_angle_deg * M_PI / 180.0);
    const float tolerance = static_cast<float>(options.occlusion_tolerance_m);
    std::vector<std::uint8_t> seen(points_W.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_W.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const Vec3d p_W = points_W[i].cast<double>();
            const Vec3d n_W = normals_W[i].cast<double>();
            for (std::size_t v = 0; v < views.size() && seen[i] == 0; ++v) {
                const Vec3d p_C = views[v].T_C_W * p_W;
                if (!(p_C.z() >= options.min_depth_m && p_C.z() <= options.max_depth_m)) continue;
                Vec2d pixel;
                if (!views[v].intrinsics.project(p_C, pixel) || !views[v].intrinsics.inside(pixel)) {
                    continue;
                }
                const Vec3d to_camera = centres_W[v] - p_W;
                const double dist = to_camera.norm();
                if (!(dist > tolerance)) continue;
                if (std::abs(n_W.dot(to_camera)) < min_cos * dist) continue;
                const Vec3f dir = (-to_camera / dist).cast<float>();
                if (occluder.occluded(centres_W[v].cast<float>(), dir, 0.0f,
                                      static_cast<float>(dist) - tolerance)) {
                    continue;
                }
                seen[i] = 1;
            }
        }
    });
    return seen;
}

}  // namespace vdbmap
