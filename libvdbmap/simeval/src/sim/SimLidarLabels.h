// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/sim/LidarModel.h"

namespace vdbmap {

/// How the simulator labels its LiDAR points (a SemanticKITTI-like ground truth, or the output
/// of an imperfect segmentation network).
struct SimLidarLabelOptions {
    /// Write SemanticKITTI's raw ids (40 road, 48 sidewalk, ...; config/label_maps/
    /// semantickitti.txt maps them back) instead of the label set's own ids.
    bool semantickitti_ids = true;
    /// Each point's class is replaced, with this probability, by another class drawn
    /// uniformly from the classes of the scene.
    double flip_rate = 0.0;
    /// Boundary noise in range-image pixels (beam x azimuth): points within this many pixels
    /// of a class change take the class of a point shifted by a random offset (one offset per
    /// 8 x 8 block), as the semantic images' --label-noise does in the image.
    int boundary_px = 0;
};

/// SemanticKITTI's raw id for a class of the default label set (docs/DATA.md). Classes without a
/// SemanticKITTI counterpart take the nearest one (traffic light -> traffic-sign 81, sky and
/// 255 -> unlabeled 0, wall -> other-structure 52).
std::uint16_t semanticKittiId(std::uint8_t our_id);

/// Labels of the returns of `scan`: the class of the hit triangle (`face_labels`), then the
/// boundary noise, then the flips; `scene_classes` are the classes flips draw from. Instance
/// ids are 0. Deterministic for `rng`'s state.
LidarLabels simulateLidarLabels(const LidarScan& scan, const LidarModel& model,
                                const std::vector<std::uint8_t>& face_labels,
                                const std::vector<std::uint8_t>& scene_classes,
                                const SimLidarLabelOptions& options, std::mt19937_64& rng);

}  // namespace vdbmap
