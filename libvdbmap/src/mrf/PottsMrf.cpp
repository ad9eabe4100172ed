// SPDX-License-Identifier: Apache-2.0
// Energy and per-node argmin of the sparse Potts MRF shared by the texture (paper Sec. 5.1)
// and semantic (Sec. 6) plugins.
#include <cmath>
#include <limits>
#include <string>

#include "mrf/MrfCheck.h"
#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"

namespace vdbmap {

namespace detail {

void checkMrfProblem(const MrfProblem& problem) {
    const std::string who = "MRF problem: ";
    if (problem.offsets.size() != problem.num_nodes + 1) {
        throw InvalidInput(who + "offsets has " + std::to_string(problem.offsets.size()) +
                           " entries, expected num_nodes+1 = " +
                           std::to_string(problem.num_nodes + 1));
    }
    if (problem.offsets.front() != 0) {
        throw InvalidInput(who + "offsets[0] must be 0, got " +
                           std::to_string(problem.offsets.front()));
    }
    for (std::size_t i = 0; i < problem.num_nodes; ++i) {
        if (problem.offsets[i + 1] < problem.offsets[i]) {
            throw InvalidInput(who + "offsets decrease at node " + std::to_string(i));
        }
    }
    if (problem.cand_labels.size() != problem.offsets.back() ||
        problem.cand_costs.size() != problem.offsets.back()) {
        throw InvalidInput(who + "cand_labels (" + std::to_string(problem.cand_labels.size()) +
                           ") and cand_costs (" + std::to_string(problem.cand_costs.size()) +
                           ") must both have offsets.back() = " +
                           std::to_string(problem.offsets.back()) + " entries");
    }
    for (std::size_t k = 0; k < problem.cand_labels.size(); ++k) {
        if (problem.cand_labels[k] >= problem.num_labels) {
            throw InvalidInput(who + "candidate " + std::to_string(k) + " has label " +
                               std::to_string(problem.cand_labels[k]) + " >= num_labels " +
                               std::to_string(problem.num_labels));
        }
        if (!std::isfinite(problem.cand_costs[k])) {
            throw InvalidInput(who + "candidate " + std::to_string(k) + " has a non-finite cost");
        }
    }
    if (!problem.edge_weights.empty() && problem.edge_weights.size() != problem.edges.size()) {
        throw InvalidInput(who + "edge_weights has " +
                           std::to_string(problem.edge_weights.size()) + " entries for " +
                           std::to_string(problem.edges.size()) + " edges");
    }
    for (std::size_t e = 0; e < problem.edges.size(); ++e) {
        const auto& ij = problem.edges[e];
        if (ij[0] >= problem.num_nodes || ij[1] >= problem.num_nodes || ij[0] == ij[1]) {
            throw InvalidInput(who + "edge " + std::to_string(e) + " (" + std::to_string(ij[0]) +
                               ", " + std::to_string(ij[1]) +
                               ") is a self edge or out of range for " +
                               std::to_string(problem.num_nodes) + " nodes");
        }
        if (!problem.edge_weights.empty() &&
            !(problem.edge_weights[e] >= 0.0f && std::isfinite(problem.edge_weights[e]))) {
            throw InvalidInput(who + "edge " + std::to_string(e) + " has weight " +
                               std::to_string(problem.edge_weights[e]) +
                               "; weights must be finite and >= 0");
        }
    }
    if (!(problem.lambda >= 0.0 && std::isfinite(problem.lambda))) {
        throw InvalidInput(who + "lambda must be finite and >= 0, got " +
                           std::to_string(problem.lambda));
    }
}

double mrfUnaryCost(const MrfProblem& problem, std::size_t node, std::uint32_t label) {
    if (label == kNoLabel) return 0.0;
    const std::uint64_t b = problem.offsets[node];
    const std::uint64_t e = problem.offsets[node + 1];
    if (b == e && problem.empty_nodes_free) return 0.0;
    for (std::uint64_t k = b; k < e; ++k) {
        if (problem.cand_labels[k] == label) return problem.cand_costs[k];
    }
    return std::numeric_limits<double>::infinity();
}

}  // namespace detail

double mrfEnergy(const MrfProblem& problem, const std::vector<std::uint32_t>& labels) {
    detail::checkMrfProblem(problem);
    if (labels.size() != problem.num_nodes) {
        throw InvalidInput("mrfEnergy: " + std::to_string(labels.size()) + " labels for " +
                           std::to_string(problem.num_nodes) + " nodes");
    }
    double energy = 0.0;
    for (std::size_t i = 0; i < problem.num_nodes; ++i) {
        energy += detail::mrfUnaryCost(problem, i, labels[i]);
    }
    double cut = 0.0;
    for (std::size_t e = 0; e < problem.edges.size(); ++e) {
        const std::uint32_t li = labels[problem.edges[e][0]];
        const std::uint32_t lj = labels[problem.edges[e][1]];
        if (li != kNoLabel && lj != kNoLabel && li != lj) cut += detail::mrfEdgeWeight(problem, e);
    }
    return energy + problem.lambda * cut;
}

std::vector<std::uint32_t> mrfArgmin(const MrfProblem& problem) {
    detail::checkMrfProblem(problem);
    std::vector<std::uint32_t> labels(problem.num_nodes, kNoLabel);
    for (std::size_t i = 0; i < problem.num_nodes; ++i) {
        const std::uint64_t b = problem.offsets[i];
        const std::uint64_t e = problem.offsets[i + 1];
        if (b == e) {
            // A free empty node may take any label at cost 0: the smallest one.
            if (problem.empty_nodes_free && problem.num_labels > 0) labels[i] = 0;
            continue;
        }
        std::uint64_t best = b;
        for (std::uint64_t k = b + 1; k < e; ++k) {
            const float c = problem.cand_costs[k];
            if (c < problem.cand_costs[best] ||
                (c == problem.cand_costs[best] &&
                 problem.cand_labels[k] < problem.cand_labels[best])) {
                best = k;
            }
        }
        labels[i] = problem.cand_labels[best];
    }
    return labels;
}

}  // namespace vdbmap
