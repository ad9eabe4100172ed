// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/eval/SemanticMetrics.h"

namespace vdbmap {

class Raycaster;

/// Where the ground-truth class changes near each prediction face: 1 if the ground truth at
/// one of 8 points on the circle of radius `radius_m` around the face's transferred
/// ground-truth point (in the plane of the prediction face) has another class than
/// transfer.label[f], else 0 (also for faces without a match). The ground truth at a point is
/// read as transferGtLabels reads it: the nearest surface within `max_distance_m`, or the
/// outer one along the face normal where surfaces are stacked closer than `stack_tolerance_m`
/// (a lane marking on the asphalt). Splitting the scores by this mask tells errors at class
/// boundaries (where label noise and the voxel size put them) from errors inside a class.
/// Parallel (TBB), deterministic. Throws InvalidInput if gt_labels does not have one label
/// per ground-truth triangle, the transfer does not have one entry per triangle, or
/// radius_m <= 0.
std::vector<std::uint8_t> nearGtClassBoundary(
    const std::vector<Vec3f>& pred_vertices,
    const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
    const GtLabelTransfer& transfer, const Raycaster& gt,
    const std::vector<std::uint8_t>& gt_labels, double radius_m, double max_distance_m = 0.5,
    double stack_tolerance_m = 0.01);

/// Number of faces labelled 255 (unknown) that share an edge (`adjacency`, pairs of face
/// indices) with a face that has a class. Throws InvalidInput for an index out of range.
std::size_t unlabelledNextToLabelled(const std::vector<std::uint8_t>& face_labels,
                                     const std::vector<std::array<std::uint32_t, 2>>& adjacency);

}  // namespace vdbmap
