// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/Truncation.h"

namespace vdbmap::test {

/// The plain truncation the closed-form tests were written against, independent of the voxel
/// size: eps in [0.10, 0.30] m, b = 0.2 m, n_ref = 100, the band behind a point not extended
/// to the next ring. (AtsdfConfig's defaults are the product's, the integrate.atsdf stage's:
/// eps in [4, 8] voxels, the band to the next ring; tests that check a closed form give their
/// settings explicitly with this.)
inline TruncationParams plainTruncationParams() {
    TruncationParams t;
    t.mode = TruncationMode::Adaptive;
    t.min_m = 0.10;
    t.max_m = 0.30;
    t.flatness_k = 1.0;
    t.reference_points = 100.0;
    t.max_along_ray_m = 0.0;
    t.grazing_band_m = 0.2;
    t.grazing_band_both_sides = false;
    t.grazing_band_to_next_ring = false;
    return t;
}

/// The plain integrator: plainTruncationParams, max weight 100, falloff l = 0.1 m, every point
/// its own ray (no merging). The other fields keep AtsdfConfig's defaults.
inline AtsdfConfig plainAtsdfConfig() {
    AtsdfConfig c;
    c.truncation = plainTruncationParams();
    c.max_weight = 100.0;
    c.falloff_m = 0.1;
    c.merge_divisions = 0;
    return c;
}

}  // namespace vdbmap::test
