// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/render/VisibilitySetup.h"

#include <memory>

#include "vdbmap/Error.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

void checkVisibilityOptions(const VisibilityOptions& options) {
    if (!(options.max_view_angle_deg > 0.0 && options.max_view_angle_deg <= 90.0)) {
        throw InvalidInput("option 'max_view_angle_deg' must be in (0, 90], got " +
                           std::to_string(options.max_view_angle_deg));
    }
    if (!(options.min_depth_m >= 0.0 && options.max_depth_m > options.min_depth_m)) {
        throw InvalidInput(
            "options 'min_depth_m' and 'max_depth_m' must satisfy 0 <= min < max, got " +
            std::to_string(options.min_depth_m) + " and " + std::to_string(options.max_depth_m));
    }
    if (!(options.occlusion_tolerance_m >= 0.0)) {
        throw InvalidInput("option 'occlusion_tolerance_m' must be >= 0, got " +
                           std::to_string(options.occlusion_tolerance_m));
    }
}

Visibility meshVisibility(const TriMesh& mesh, const std::vector<View>& views,
                          const VisibilityOptions& options, const std::string& progress_label,
                          bool quiet, const TriMesh* occluders) {
    std::unique_ptr<Raycaster> occluder;
    if (options.occlusion_test) {
        occluder = std::make_unique<Raycaster>(Raycaster::fromMesh(occluders ? *occluders : mesh));
    }
    Progress progress(progress_label, views.size(), quiet);
    return computeVisibility(mesh, views, options, occluder.get(), &progress);
}

}  // namespace vdbmap
