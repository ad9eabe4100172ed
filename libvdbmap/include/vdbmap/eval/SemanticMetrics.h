// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

class Raycaster;

/// Per-class scores (area-weighted).
struct ClassScore {
    std::uint8_t id = 0;
    double gt_area_m2 = 0;  ///< prediction area whose ground-truth class is `id`
    double accuracy = 0;    ///< recall of the class
    double iou = 0;
};

/// Semantic metrics of a labelled prediction mesh.
struct SemanticMetrics {
    double overall_accuracy = 0;     ///< correct area / matched area (255 counts as wrong)
    double mean_class_accuracy = 0;  ///< over classes present in the ground truth
    double miou = 0;                 ///< over classes present in the ground truth
    double unlabelled_fraction = 0;  ///< area of 255 faces / matched area
    double matched_area_m2 = 0;      ///< prediction area with a ground-truth face in reach
    double unmatched_area_m2 = 0;    ///< prediction area farther than max_distance_m from gt
    std::vector<ClassScore> classes;
};

/// Transfers ground-truth labels to each prediction face through the nearest ground-truth
/// face of its centroid (within `max_distance_m`; farther faces are unmatched and not scored)
/// and scores them area-weighted. Ground-truth faces labelled 255 are not scored. Throws
/// InvalidInput if a label vector's size does not match its triangles.
SemanticMetrics evaluateSemantics(const std::vector<Vec3f>& pred_vertices,
                                  const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                  const std::vector<std::uint8_t>& pred_labels,
                                  const Raycaster& gt, const std::vector<std::uint8_t>& gt_labels,
                                  double max_distance_m = 0.5);

}  // namespace vdbmap
