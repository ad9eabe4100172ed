// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/StageVisibility.h"

#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/render/VisibilitySetup.h"

namespace vdbmap {

StageVisibility stageVisibility(Context& ctx, const MeshArrays& mesh,
                                const std::vector<View>& views, const VisibilityOptions& options,
                                const ScanOcclusionOptions* scan, const std::string& stage) {
    const auto moving = ctx.movingReturns();
    StageVisibility out;
    out.key = visibilityKey(mesh, ctx.occluderMesh(), views, options, scan, moving.get());
    if (auto kept = ctx.takeVisibility(out.key, options.max_view_angle_deg)) {
        out.shared = std::move(*kept);
        out.reused = true;
        return out;
    }
    out.shared.max_view_angle_deg = options.max_view_angle_deg;
    out.shared.visibility = meshVisibility(ctx.mesh(), views, options, stage + " visibility",
                                           ctx.quiet(), &ctx.occluderMesh());
    if (scan) {
        // A view must not use a face that something in front hid when the image was taken, even
        // if the map lacks it (a moving car): the scan nearest in time tells. The returns
        // removed as moving hide by a tighter rule (ScanOcclusionOptions::moving_*).
        Timer timer;
        const Dataset& dataset = ctx.dataset();
        Progress progress(stage + " scan occlusion", views.size(), ctx.quiet());
        removeScanOccluded(out.shared.visibility, mesh, views, datasetViewScans(dataset, views),
                           *scan, &progress,
                           moving ? movingViewScans(dataset, views, *moving) : ViewScanFn{},
                           &out.shared.scan_hidden_cos);
        progress.finish();
        out.scan_occlusion_s = timer.elapsedSeconds();
    }
    return out;
}

}  // namespace vdbmap
