// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/render/ScanOcclusion.h"
#include "vdbmap/render/Visibility.h"
#include "vdbmap/render/VisibilityKey.h"

namespace vdbmap {

class Context;

/// A mesh stage's visibility of ctx.mesh() after the scan occlusion test.
struct StageVisibility {
    std::string key;              ///< visibilityKey() of its inputs: keep it under this
    SharedVisibility shared;
    bool reused = false;          ///< taken from an earlier stage (Context::takeVisibility)
    double scan_occlusion_s = 0;  ///< the scan test's time, when it ran here
};

/// The visibility texture.mrf and semantic.mrf start from: the one an earlier stage of `ctx`
/// kept for the same inputs (Context::takeVisibility, narrowed to options.max_view_angle_deg),
/// else meshVisibility of ctx.mesh() in `views` with ctx.occluderMesh() as occluder, then with
/// `scan` (non-null) removeScanOccluded with the dataset's scans and ctx's moving returns.
/// `mesh` is meshArrays() of ctx.mesh() as the stage indexes its faces. Progress bars
/// "<stage> visibility" and "<stage> scan occlusion" (none under --quiet). Hand it on after use
/// with ctx.keepVisibility(result.key, std::move(result.shared)). Throws what those throw.
StageVisibility stageVisibility(Context& ctx, const MeshArrays& mesh,
                                const std::vector<View>& views, const VisibilityOptions& options,
                                const ScanOcclusionOptions* scan, const std::string& stage);

}  // namespace vdbmap
