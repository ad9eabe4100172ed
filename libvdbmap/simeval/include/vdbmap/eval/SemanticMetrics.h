// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <utility>
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
    /// Where the rest of its area went: (predicted class, area in m^2) for every other
    /// predicted class (255 = unlabelled), largest first. A row of the confusion matrix.
    std::vector<std::pair<std::uint8_t, double>> confused_m2;
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

/// The ground truth behind each prediction face.
struct GtLabelTransfer {
    std::vector<int> label;         ///< ground-truth class per face; -1 = no gt face in reach
    std::vector<double> area_m2;    ///< area of the prediction face
    std::vector<Vec3f> gt_point_W;  ///< the ground-truth point the label came from
    std::vector<std::uint32_t> gt_face;  ///< the ground-truth triangle of that point
    std::size_t stacked_resolved = 0;    ///< faces labelled by the outer of stacked surfaces
};

/// Transfers ground-truth classes to prediction faces. The class is that of the nearest
/// ground-truth face to the face centroid (within `max_distance_m`; farther faces get -1),
/// except where two ground-truth surfaces are stacked closer than `stack_tolerance_m` (a lane
/// marking 5 mm above the asphalt): there the surface seen from outside along the
/// prediction face's normal wins, if it is no more than `stack_tolerance_m` farther than the
/// nearest one. Without this, a marking face whose centroid lies below the middle of the
/// two layers would be scored against the asphalt. Parallel (TBB), deterministic. Throws
/// InvalidInput if gt_labels does not have one label per ground-truth triangle.
GtLabelTransfer transferGtLabels(const std::vector<Vec3f>& pred_vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                 const Raycaster& gt, const std::vector<std::uint8_t>& gt_labels,
                                 double max_distance_m = 0.5, double stack_tolerance_m = 0.01);

/// Area-weighted scores of `pred_labels` against a transfer. Faces with mask[f] == 0 are
/// left out (neither matched nor unmatched); `mask` null = all faces. Ground-truth class 255
/// is not scored. Throws InvalidInput on size mismatches.
SemanticMetrics scoreSemantics(const GtLabelTransfer& transfer,
                               const std::vector<std::uint8_t>& pred_labels,
                               const std::vector<std::uint8_t>* mask = nullptr);

/// transferGtLabels + scoreSemantics over all faces. Throws InvalidInput if a label vector's
/// size does not match its triangles.
SemanticMetrics evaluateSemantics(const std::vector<Vec3f>& pred_vertices,
                                  const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                  const std::vector<std::uint8_t>& pred_labels,
                                  const Raycaster& gt, const std::vector<std::uint8_t>& gt_labels,
                                  double max_distance_m = 0.5);

}  // namespace vdbmap
