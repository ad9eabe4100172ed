// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace vdbmap {

/// A label that means "none" (a node with no candidate when empty nodes are not free).
inline constexpr std::uint32_t kNoLabel = std::numeric_limits<std::uint32_t>::max();

/// A sparse multi-label MRF with a Potts smoothness term, the form shared by texture view
/// selection (labels = views, paper Sec. 5.1) and semantic fusion (labels = classes, Sec. 6):
///   E(l) = sum_i D_i(l_i) + lambda * sum_{(i,j) in edges} w_ij * [l_i != l_j].
/// Node i may take only its candidate labels, with unary costs D_i; a node without candidates
/// takes any label at cost 0 if `empty_nodes_free`, otherwise it is fixed to kNoLabel and
/// its edges are ignored.
struct MrfProblem {
    std::size_t num_nodes = 0;
    std::size_t num_labels = 0;
    std::vector<std::uint64_t> offsets;       ///< size num_nodes+1 (CSR over candidates)
    std::vector<std::uint32_t> cand_labels;   ///< candidate labels of all nodes
    std::vector<float> cand_costs;            ///< unary cost of each candidate
    std::vector<std::array<std::uint32_t, 2>> edges;  ///< undirected, i != j
    std::vector<float> edge_weights;          ///< empty = all 1
    double lambda = 1.0;
    bool empty_nodes_free = false;
};

struct MrfSolution {
    std::vector<std::uint32_t> labels;  ///< per node
    double initial_energy = 0;          ///< of the per-node argmin labelling
    double final_energy = 0;
    int sweeps = 0;                     ///< alpha-expansion sweeps over all labels
};

struct AlphaExpansionOptions {
    int max_sweeps = 5;
    /// Solve connected components of the edge graph in parallel (TBB). Same result.
    bool parallel_components = true;
};

/// Energy of a labelling (the formula above). kNoLabel nodes cost 0 and cut no edge.
double mrfEnergy(const MrfProblem& problem, const std::vector<std::uint32_t>& labels);

/// Per-node argmin of the unary cost (ties: smallest label); lambda = 0 solution.
std::vector<std::uint32_t> mrfArgmin(const MrfProblem& problem);

/// Alpha-expansion with graph cuts (Boykov, Veksler, Zabih 2001), each move an exact minimum
/// cut (Boost Graph's Boykov-Kolmogorov max-flow). Starts from mrfArgmin, never raises the energy, stops when a sweep
/// brings no improvement. lambda = 0 returns mrfArgmin exactly. Throws InvalidInput on an
/// inconsistent problem (sizes, label out of range).
MrfSolution solveAlphaExpansion(const MrfProblem& problem,
                                const AlphaExpansionOptions& options = {});

}  // namespace vdbmap
