// SPDX-License-Identifier: Apache-2.0
#include "ViewSelection.h"

#include <algorithm>

#include "vdbmap/Error.h"

namespace vdbmap::texture {

MrfProblem buildViewSelectionProblem(const Visibility& vis,
                                     const std::vector<ObservationStats>& stats,
                                     const std::vector<char>& keep,
                                     const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                     std::size_t num_views, double lambda,
                                     std::size_t max_candidates) {
    if (stats.size() != vis.obs.size() || keep.size() != vis.obs.size()) {
        throw InvalidInput("texture: observation statistics (" + std::to_string(stats.size()) +
                           ") and flags (" + std::to_string(keep.size()) +
                           ") must match the visibility (" + std::to_string(vis.obs.size()) + ")");
    }
    // Candidates: the kept observations, optionally only the max_candidates of highest E_Q.
    std::vector<char> candidate(keep.begin(), keep.end());
    if (max_candidates > 0) {
        std::vector<std::uint64_t> kept;
        for (std::size_t f = 0; f < vis.numFaces(); ++f) {
            kept.clear();
            for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
                if (keep[i]) kept.push_back(i);
            }
            if (kept.size() <= max_candidates) continue;
            std::nth_element(kept.begin(), kept.begin() + (max_candidates - 1), kept.end(),
                             [&](std::uint64_t a, std::uint64_t b) {
                                 return stats[a].quality > stats[b].quality ||
                                        (stats[a].quality == stats[b].quality && a < b);
                             });
            for (std::size_t k = max_candidates; k < kept.size(); ++k) candidate[kept[k]] = 0;
        }
    }
    MrfProblem problem;
    problem.num_nodes = vis.numFaces();
    problem.num_labels = num_views;
    problem.lambda = lambda;
    problem.empty_nodes_free = false;
    problem.offsets.resize(problem.num_nodes + 1, 0);
    for (std::size_t f = 0; f < problem.num_nodes; ++f) {
        std::uint64_t count = 0;
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
            count += candidate[i] != 0;
        }
        problem.offsets[f + 1] = problem.offsets[f] + count;
    }
    problem.cand_labels.resize(problem.offsets.back());
    problem.cand_costs.resize(problem.offsets.back());
    for (std::size_t f = 0; f < problem.num_nodes; ++f) {
        float max_quality = 0;
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
            if (candidate[i]) max_quality = std::max(max_quality, stats[i].quality);
        }
        std::uint64_t out = problem.offsets[f];
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
            if (!candidate[i]) continue;
            problem.cand_labels[out] = vis.obs[i].view;
            // E_D = 1 - E_Q / max E_Q over the face's candidates (documented above).
            problem.cand_costs[out] =
                max_quality > 0 ? 1.0f - stats[i].quality / max_quality : 0.0f;
            ++out;
        }
    }
    problem.edges = adjacency;
    return problem;
}

MrfSolution selectViews(const MrfProblem& problem, bool use_mrf) {
    if (use_mrf) return solveAlphaExpansion(problem);
    MrfSolution solution;
    solution.labels = mrfArgmin(problem);
    solution.initial_energy = mrfEnergy(problem, solution.labels);
    solution.final_energy = solution.initial_energy;
    return solution;
}

}  // namespace vdbmap::texture
