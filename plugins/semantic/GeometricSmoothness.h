// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "SemanticVotes.h"
#include "vdbmap/core/Types.h"

namespace vdbmap::semantic {

/// Settings of the geometry-aware smoothness weights.
struct GeometricSmoothnessOptions {
    double normal_sigma_deg = 20.0;  ///< angle between the two face normals
    double height_sigma_m = 0.03;    ///< height step between the two centroids (see below)
    double min_weight = 0.01;        ///< floor, so that a fill still crosses every edge
};

/// Weight w_ij of the Potts term lambda * w_ij * [l_i != l_j] for every face pair of
/// `adjacency` (paper Eq. 3's E_S made geometry-aware): it falls across sharp normal changes
/// and height steps, where class boundaries of street scenes lie (kerbs, walls, car bodies):
///
///   w_ij = max(min_weight, exp(-theta_ij^2 / (2 sigma_n^2) - h_ij^2 / (2 sigma_h^2)))
///   theta_ij = angle between the face normals n_i, n_j
///   h_ij     = |(c_j - c_i) . up| * min(|n_i . up|, |n_j . up|)
///
/// h_ij is the height difference of the centroids c, counted only as far as both faces are
/// level (so that neighbours on a wall, which differ in height by construction, are not
/// cut apart). `up` is the world's up direction (unit). Degenerate faces count as level with
/// normal `up`. Throws InvalidInput on an index out of range or bad sigmas.
std::vector<float> geometricEdgeWeights(const std::vector<Vec3f>& vertices,
                                        const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                        const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                        const Vec3f& up,
                                        const GeometricSmoothnessOptions& options);

/// The fill only: sets w_ij = 1 (the paper's uniform Potts term) on every edge between two
/// faces that some source voted for, where the data decide and lower weights would only
/// weaken the denoising. Throws InvalidInput on a size mismatch.
void uniformBetweenObserved(std::vector<float>& weights,
                            const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                            const FaceVotes& votes);

}  // namespace vdbmap::semantic
