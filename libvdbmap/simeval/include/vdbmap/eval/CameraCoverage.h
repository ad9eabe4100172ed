// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap {

class Raycaster;

/// When a surface point counts as seen by a camera.
struct CoverageOptions {
    double min_depth_m = 0.1;    ///< in front of the camera by at least this
    double max_depth_m = 200.0;  ///< camera-z limit
    /// Between the surface normal (either side) and the camera ray.
    double max_view_angle_deg = 90.0;
    double occlusion_tolerance_m = 0.02;  ///< a hit closer than this to the point is no occluder
};

/// For every surface point (with its unit normal), 1 if at least one view sees it: the point
/// projects inside the image (docs/DATA.md pixel convention), its depth is in
/// [min_depth_m, max_depth_m], the camera ray meets the surface within max_view_angle_deg of
/// its normal (either side: closed objects hide their back faces through the occlusion test,
/// so the winding of the ground-truth faces does not matter), and
/// `occluder` (the scene) has no hit on the ray from the camera centre closer than the point's
/// distance minus occlusion_tolerance_m; else 0. Parallel over points (TBB), deterministic.
/// Throws InvalidInput if the sizes of points and normals differ, on bad options, or on a view
/// with a non-positive image size or focal length.
std::vector<std::uint8_t> pointsSeenByViews(const std::vector<Vec3f>& points_W,
                                            const std::vector<Vec3f>& normals_W,
                                            const std::vector<View>& views,
                                            const Raycaster& occluder,
                                            const CoverageOptions& options = {});

}  // namespace vdbmap
