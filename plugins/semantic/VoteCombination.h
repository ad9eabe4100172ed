// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "SemanticVotes.h"

namespace vdbmap::semantic {

/// Which sources voted for a face.
enum FaceSource : std::uint8_t { kSourceNone = 0, kSourceImages = 1, kSourceLidar = 2 };

/// The two sources' votes combined into one distribution per face, the input of the data term
/// E_D (paper Eq. semantic_mrf_energy_function, extended to LiDAR points):
///
///   P_I(F_i, C_m) = sum_k S_Ik(F_i, C_m) / sum_n sum_k S_Ik(F_i, C_n)     (images, paper)
///   P_L(F_i, C_m) = sum_p w_p(F_i) [c_p = m] / sum_p w_p(F_i)             (LiDAR points p)
///   p(F_i, C_m)   = (a_I P_I + w_L a_L P_L) / (a_I + w_L a_L)
///   E_D(F_i, C_m) = -log(max(p(F_i, C_m), floor))
///
/// with w_p(F_i) = 1 - (d / r)^2 for a point at distance d < r from the face, a_I = 1 if a
/// view voted for the face (else 0), a_L = 1 if a point did, and w_L = `lidar_weight`. Each
/// source is normalised first, so that pixels^2 and point weights need no common unit, and
/// w_L is the weight of the LiDAR's opinion against the images' where both saw the face.
/// A face neither saw keeps no votes (the MRF fills it). The result's weights are p (they sum
/// to 1 per face). `sources` (may be null) receives kSourceImages | kSourceLidar per face.
/// Either input may be empty (no faces) when that source is off. Throws InvalidInput if the
/// face or class counts differ or lidar_weight < 0.
FaceVotes combineVotes(const FaceVotes& images, const FaceVotes& lidar, double lidar_weight,
                       std::vector<std::uint8_t>* sources = nullptr);

}  // namespace vdbmap::semantic
