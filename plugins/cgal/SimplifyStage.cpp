// SPDX-License-Identifier: Apache-2.0
#include "SimplifyStage.h"

#include <string>

#include "MeshSimplify.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap::cgal {

void SimplifyStage::declareOptions(OptionSpec& spec) {
    spec.add("target_ratio", "Keep at most this fraction of the mesh edges, in (0, 1]",
             target_ratio_, 0.25);
    spec.add("max_error_m", "Largest distance a collapse may move the surface", max_error_m_,
             0.02, "m");
}

void SimplifyStage::initialize() {
    if (!(target_ratio_ > 0.0 && target_ratio_ <= 1.0)) {
        failConfig("option 'target_ratio' must be in (0, 1], got " + std::to_string(target_ratio_));
    }
    if (!(max_error_m_ > 0.0)) {
        failConfig("option 'max_error_m' must be > 0, got " + std::to_string(max_error_m_));
    }
}

void SimplifyStage::declareLayers(LayerSpec& spec) const {
    spec.reads(layers::kMesh);
    spec.writes(layers::kMesh);
}

void SimplifyStage::run(Context& ctx) {
    if (ctx.hasTile()) {
        // Edge collapses would move the shared border of two tiles differently in each.
        fail("does not run in tiled runs yet (it would open cracks at tile borders); remove "
             "the `tiling:` section or this stage");
    }
    Timer timer;
    const SimplifyResult r = simplifyMesh(ctx.mesh(), {target_ratio_, max_error_m_});
    const std::string stage(name());
    ctx.report().stage(stage, "faces_in", r.faces_in);
    ctx.report().stage(stage, "faces_out", r.faces_out);
    ctx.report().stage(stage, "faces_skipped_non_manifold", r.faces_skipped);
    ctx.report().stage(stage, "collapsed_edges", r.collapsed_edges);
    logInfo(stage + ": " + std::to_string(r.faces_in) + " -> " + std::to_string(r.faces_out) +
            " faces in " + std::to_string(timer.elapsedSeconds()) + " s");
}

}  // namespace vdbmap::cgal
