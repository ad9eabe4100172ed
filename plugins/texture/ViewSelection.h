// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "TextureTypes.h"
#include "vdbmap/mrf/PottsMrf.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::texture {

/// The view-selection MRF of the paper (Sec. 5.1):
///   E = sum_F E_D(F, I_F) + lambda * sum_{(F, G) adjacent} [I_F != I_G]   (Potts E_S)
/// Nodes are faces, labels are views; a face's candidates are its visible views that `keep`
/// retains. The data cost normalises the paper's quality E_Q per face:
///   E_D(F, I) = 1 - E_Q(F, I) / max_{I' candidate of F} E_Q(F, I'),
/// so each face's best view costs 0, the others up to 1, and lambda weighs one seam edge
/// against one face's full preference range, independent of image contrast. A face whose
/// candidates all have E_Q = 0 gets cost 0 for all of them. With `max_candidates` > 0 only the
/// that many views of highest E_Q stay candidates (the best view always does): alpha-expansion
/// time grows with the candidates, and a face's low-quality views are rarely chosen.
MrfProblem buildViewSelectionProblem(const Visibility& vis,
                                     const std::vector<ObservationStats>& stats,
                                     const std::vector<char>& keep,
                                     const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                     std::size_t num_views, double lambda,
                                     std::size_t max_candidates = 0);

/// Solves the problem: alpha-expansion (vdbmap/mrf/PottsMrf.h) when `use_mrf`, else the
/// per-face best view (mrfArgmin; the energies are still reported). Labels are view indices,
/// kNoLabel for faces without a candidate.
MrfSolution selectViews(const MrfProblem& problem, bool use_mrf);

}  // namespace vdbmap::texture
