// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "vdbmap/mesh/TriMesh.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap {

/// Checks the visibility options as stages declare them. Throws InvalidInput naming the first
/// bad option by its YAML key ('max_view_angle_deg' outside (0, 90], 'min_depth_m' /
/// 'max_depth_m' not 0 <= min < max, 'occlusion_tolerance_m' < 0) and its value.
void checkVisibilityOptions(const VisibilityOptions& options);

/// The visibility set-up shared by the texture and semantic stages: builds the Embree BVH of
/// `occluders` (the mesh itself when null; a tiled run passes Context::occluderMesh(), the tile
/// with a margin of its neighbours) when options.occlusion_test, and runs computeVisibility with
/// a progress bar "<progress_label>" ticked per view (none if `quiet`). The BVH is freed on
/// return. Throws what computeVisibility throws.
Visibility meshVisibility(const TriMesh& mesh, const std::vector<View>& views,
                          const VisibilityOptions& options, const std::string& progress_label,
                          bool quiet, const TriMesh* occluders = nullptr);

}  // namespace vdbmap
