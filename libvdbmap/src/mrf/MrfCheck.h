// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>

#include "vdbmap/mrf/PottsMrf.h"

namespace vdbmap::detail {

/// Throws InvalidInput naming the field and the bad value if the problem is inconsistent:
/// offsets size / monotonicity, candidate arrays of different lengths, a label >= num_labels,
/// an edge endpoint out of range or a self edge, edge_weights of the wrong size or a negative
/// or non-finite weight, a negative or non-finite lambda, a non-finite unary cost.
void checkMrfProblem(const MrfProblem& problem);

/// Unary cost of `label` at node i: the candidate's cost, 0 for a free empty node, and
/// +infinity for a label that is not a candidate. kNoLabel costs 0.
double mrfUnaryCost(const MrfProblem& problem, std::size_t node, std::uint32_t label);

/// True if node i has no candidates and is therefore fixed to kNoLabel.
inline bool mrfNodeFixedToNone(const MrfProblem& problem, std::size_t node) {
    return !problem.empty_nodes_free && problem.offsets[node] == problem.offsets[node + 1];
}

/// Potts weight w_ij of edge e (1 when edge_weights is empty).
inline double mrfEdgeWeight(const MrfProblem& problem, std::size_t e) {
    return problem.edge_weights.empty() ? 1.0 : static_cast<double>(problem.edge_weights[e]);
}

}  // namespace vdbmap::detail
