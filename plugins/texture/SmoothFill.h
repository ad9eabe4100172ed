// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap::texture {

/// Colours for the faces no view saw, diffused from the textured border over the face graph:
/// the harmonic (discrete Laplace) fill
///
///   sum_{j in N(i)} w_ij (x_i - x_j) = 0   for every untextured face i,   x_k = c_k fixed
///                                           for every textured face k,
///
/// N(i) the faces sharing an edge with i (`adjacency`), w_ij = `edge_weights` (null: all 1;
/// creaseWeights makes colours stop at creases, so a car's colour does not run onto the road). One sparse symmetric positive-definite
/// system over the untextured faces, solved with Eigen's SimplicialLDLT for the three channels
/// at once. `known[f]` marks the textured faces, `color[f]` their colour (any 3 channels).
/// Faces of a component without any textured face keep their colour and get filled[f] = 0;
/// every other face gets filled[f] = 1 (textured faces keep theirs). Throws InvalidInput on
/// size mismatches, an adjacency index out of range, or a failed factorisation.
std::vector<Vec3f> harmonicFill(const std::vector<char>& known, const std::vector<Vec3f>& color,
                                const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                std::vector<char>& filled,
                                const std::vector<float>* edge_weights = nullptr);

/// w_ij = max(min_weight, exp(-theta_ij^2 / (2 sigma^2))), theta_ij the angle between the
/// normals of the two faces of each adjacency pair. Throws InvalidInput on an index out of
/// range.
std::vector<float> creaseWeights(const std::vector<Vec3f>& vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& faces,
                                 const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                 double sigma_deg = 20.0, double min_weight = 0.01);

}  // namespace vdbmap::texture
