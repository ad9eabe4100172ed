// SPDX-License-Identifier: Apache-2.0
// Alpha-expansion (Boykov, Veksler, Zabih 2001) for the sparse Potts MRF, with the binary
// expansion move built as in Kolmogorov and Zabih (2004) and solved as a minimum cut
// (mrf/BinaryCut.h: Boost Graph's Boykov-Kolmogorov max-flow). One solver for the texture view
// selection (paper Sec. 5.1) and the semantic fusion (paper Sec. 6, Eq.
// semantic_mrf_energy_function).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>

#include "mrf/BinaryCut.h"
#include "mrf/MrfCheck.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/mrf/PottsMrf.h"
#include "vdbmap/core/UnionFind.h"

namespace vdbmap {

namespace {

/// Node -> (neighbour, lambda * w_ij) in CSR form, without the nodes fixed to kNoLabel.
struct Adjacency {
    std::vector<std::uint64_t> offsets;
    std::vector<std::uint32_t> neighbours;
    std::vector<double> weights;
};

Adjacency buildAdjacency(const MrfProblem& problem) {
    Adjacency adj;
    adj.offsets.assign(problem.num_nodes + 1, 0);
    auto usable = [&](std::size_t e) {
        const auto& ij = problem.edges[e];
        return !detail::mrfNodeFixedToNone(problem, ij[0]) &&
               !detail::mrfNodeFixedToNone(problem, ij[1]);
    };
    for (std::size_t e = 0; e < problem.edges.size(); ++e) {
        if (!usable(e)) continue;
        ++adj.offsets[problem.edges[e][0] + 1];
        ++adj.offsets[problem.edges[e][1] + 1];
    }
    std::partial_sum(adj.offsets.begin(), adj.offsets.end(), adj.offsets.begin());
    adj.neighbours.resize(adj.offsets.back());
    adj.weights.resize(adj.offsets.back());
    std::vector<std::uint64_t> cursor(adj.offsets.begin(), adj.offsets.end() - 1);
    for (std::size_t e = 0; e < problem.edges.size(); ++e) {
        if (!usable(e)) continue;
        const double w = problem.lambda * detail::mrfEdgeWeight(problem, e);
        const auto [i, j] = problem.edges[e];
        adj.neighbours[cursor[i]] = j;
        adj.weights[cursor[i]++] = w;
        adj.neighbours[cursor[j]] = i;
        adj.weights[cursor[j]++] = w;
    }
    return adj;
}

/// Connected components of the adjacency graph: nodes grouped per component, ascending node
/// id inside a component, components ordered by their smallest node.
struct Components {
    std::vector<std::uint32_t> nodes;
    std::vector<std::uint64_t> offsets;
};

Components findComponents(const MrfProblem& problem, const Adjacency& adj) {
    const std::size_t n = problem.num_nodes;
    // uniteSets keeps the smaller id as the root: the root is the component's smallest node.
    std::vector<std::uint32_t> parent = makeDisjointSets(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::uint64_t k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k) {
            uniteSets(parent, static_cast<std::uint32_t>(i), adj.neighbours[k]);
        }
    }
    std::vector<std::uint32_t> comp_of(n);
    std::vector<std::uint32_t> comp_index(n, 0);
    std::uint32_t num_components = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t r = findRoot(parent, static_cast<std::uint32_t>(i));
        if (r == i) comp_index[i] = num_components++;
        comp_of[i] = comp_index[r];
    }
    Components comps;
    comps.offsets.assign(num_components + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++comps.offsets[comp_of[i] + 1];
    std::partial_sum(comps.offsets.begin(), comps.offsets.end(), comps.offsets.begin());
    comps.nodes.resize(n);
    std::vector<std::uint64_t> cursor(comps.offsets.begin(), comps.offsets.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        comps.nodes[cursor[comp_of[i]]++] = static_cast<std::uint32_t>(i);
    }
    return comps;
}

/// Alpha-expansion on one connected component. `labels` holds the global labelling and
/// `local_of` the global -> local map; only this component's entries are written.
class ComponentSolver {
public:
    ComponentSolver(const MrfProblem& problem, const Adjacency& adj,
                    const std::uint32_t* nodes, std::size_t size,
                    std::vector<std::uint32_t>& labels, std::vector<std::int32_t>& local_of)
        : problem_(problem), adj_(adj), nodes_(nodes), size_(size), labels_(labels),
          local_of_(local_of) {}

    /// Returns the number of sweeps run.
    int solve(int max_sweeps) {
        for (std::size_t i = 0; i < size_; ++i) local_of_[nodes_[i]] = static_cast<int>(i);
        buildLabelIndex();
        cur_cost_.resize(size_);
        for (std::size_t i = 0; i < size_; ++i) {
            cur_cost_[i] = detail::mrfUnaryCost(problem_, nodes_[i], labels_[nodes_[i]]);
        }
        var_of_.assign(size_, -1);
        int sweeps = 0;
        for (; sweeps < max_sweeps;) {
            ++sweeps;
            bool improved = false;
            for (std::size_t a = 0; a < alphas_.size(); ++a) improved |= expand(a);
            if (!improved) break;
        }
        return sweeps;
    }

private:
    // Candidate index of the component: for each alpha, the local nodes that may take it.
    void buildLabelIndex() {
        struct Entry {
            std::uint32_t label;
            std::uint32_t local;
            double cost;
        };
        std::vector<Entry> entries;
        for (std::size_t i = 0; i < size_; ++i) {
            const std::size_t node = nodes_[i];
            const std::uint64_t b = problem_.offsets[node];
            const std::uint64_t e = problem_.offsets[node + 1];
            if (b == e) {
                free_nodes_.push_back(static_cast<std::uint32_t>(i));
                continue;
            }
            for (std::uint64_t k = b; k < e; ++k) {
                entries.push_back({problem_.cand_labels[k], static_cast<std::uint32_t>(i),
                                   static_cast<double>(problem_.cand_costs[k])});
            }
        }
        std::stable_sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
            return x.label < y.label || (x.label == y.label && x.local < y.local);
        });
        alpha_offsets_.push_back(0);
        for (std::size_t k = 0; k < entries.size(); ++k) {
            if (k > 0 && entries[k].label != entries[k - 1].label) {
                alpha_offsets_.push_back(k);
            }
            if (k == 0 || entries[k].label != entries[k - 1].label) {
                alphas_.push_back(entries[k].label);
            }
            entry_local_.push_back(entries[k].local);
            entry_cost_.push_back(entries[k].cost);
        }
        alpha_offsets_.push_back(entries.size());
        if (entries.empty()) alpha_offsets_.assign(1, 0);
    }

    // One expansion move for alphas_[a]; returns true if it lowered the energy.
    bool expand(std::size_t a) {
        const std::uint32_t alpha = alphas_[a];
        vars_.clear();
        var_alpha_cost_.clear();
        for (std::size_t k = alpha_offsets_[a]; k < alpha_offsets_[a + 1]; ++k) {
            const std::uint32_t i = entry_local_[k];
            if (labels_[nodes_[i]] == alpha) continue;
            var_of_[i] = static_cast<int>(vars_.size());
            vars_.push_back(i);
            var_alpha_cost_.push_back(entry_cost_[k]);
        }
        for (const std::uint32_t i : free_nodes_) {
            if (labels_[nodes_[i]] == alpha) continue;
            var_of_[i] = static_cast<int>(vars_.size());
            vars_.push_back(i);
            var_alpha_cost_.push_back(0.0);
        }
        if (vars_.empty()) return false;

        // Binary move: x_i = 0 keeps l_i, x_i = 1 takes alpha. E0/E1 are the unary costs of
        // the two choices, with the Potts terms towards fixed neighbours folded in.
        const std::size_t nv = vars_.size();
        e0_.assign(nv, 0.0);
        e1_.assign(nv, 0.0);
        cut_.reset(nv);
        for (std::size_t v = 0; v < nv; ++v) {
            const std::uint32_t i = vars_[v];
            const std::uint32_t li = labels_[nodes_[i]];
            e0_[v] += cur_cost_[i];
            e1_[v] += var_alpha_cost_[v];
            const std::size_t node = nodes_[i];
            for (std::uint64_t k = adj_.offsets[node]; k < adj_.offsets[node + 1]; ++k) {
                const std::uint32_t gj = adj_.neighbours[k];
                const double w = adj_.weights[k];
                const std::uint32_t lj = labels_[gj];
                const int u = var_of_[local_of_[gj]];
                if (u < 0) {
                    e0_[v] += li != lj ? w : 0.0;
                    e1_[v] += alpha != lj ? w : 0.0;
                    continue;
                }
                if (static_cast<std::size_t>(u) < v) continue;  // each pair once
                // Kolmogorov-Zabih: with B = C = w, D = 0 and A = w [l_i != l_j],
                // E = A + (w - A) x_i - w x_j + (2w - A)(1 - x_i) x_j.
                const double pair_a = li != lj ? w : 0.0;
                e1_[v] += w - pair_a;
                e0_[u] += w;
                cut_.addPair(v, static_cast<std::size_t>(u), 2.0 * w - pair_a);
            }
        }
        for (std::size_t v = 0; v < nv; ++v) cut_.addUnary(v, e0_[v], e1_[v]);
        cut_.solve(take_);
        const bool improved = applyIfBetter(alpha);
        for (const std::uint32_t i : vars_) var_of_[i] = -1;
        return improved;
    }

    // Applies the move if it lowers the energy (exactly evaluated), else leaves the labels.
    bool applyIfBetter(std::uint32_t alpha) {
        const std::size_t nv = vars_.size();
        double delta = 0.0;
        double scale = 0.0;
        for (std::size_t v = 0; v < nv; ++v) {
            if (!take_[v]) continue;
            const std::uint32_t i = vars_[v];
            const std::size_t node = nodes_[i];
            const std::uint32_t li = labels_[node];
            delta += var_alpha_cost_[v] - cur_cost_[i];
            scale += std::abs(cur_cost_[i]);
            for (std::uint64_t k = adj_.offsets[node]; k < adj_.offsets[node + 1]; ++k) {
                const std::uint32_t gj = adj_.neighbours[k];
                const int u = var_of_[local_of_[gj]];
                const bool j_moves = u >= 0 && take_[u];
                if (j_moves && static_cast<std::size_t>(u) < v) continue;  // counted once
                const std::uint32_t lj = labels_[gj];
                const std::uint32_t lj_new = j_moves ? alpha : lj;
                const double w = adj_.weights[k];
                delta += (alpha != lj_new ? w : 0.0) - (li != lj ? w : 0.0);
                scale += w;
            }
        }
        // The all-keep labelling is a feasible cut, so the optimal move never costs more.
        assert(delta <= 1e-6 * (1.0 + scale));
        if (!(delta < -1e-12 * (1.0 + scale))) return false;
        for (std::size_t v = 0; v < nv; ++v) {
            if (!take_[v]) continue;
            labels_[nodes_[vars_[v]]] = alpha;
            cur_cost_[vars_[v]] = var_alpha_cost_[v];
        }
        return true;
    }

    const MrfProblem& problem_;
    const Adjacency& adj_;
    const std::uint32_t* nodes_;
    std::size_t size_;
    std::vector<std::uint32_t>& labels_;
    std::vector<std::int32_t>& local_of_;

    std::vector<std::uint32_t> alphas_;
    std::vector<std::size_t> alpha_offsets_;
    std::vector<std::uint32_t> entry_local_;
    std::vector<double> entry_cost_;
    std::vector<std::uint32_t> free_nodes_;
    std::vector<double> cur_cost_;
    std::vector<int> var_of_;
    std::vector<std::uint32_t> vars_;
    std::vector<double> var_alpha_cost_;
    std::vector<double> e0_, e1_;
    std::vector<char> take_;
    detail::BinaryCut cut_;
};

}  // namespace

MrfSolution solveAlphaExpansion(const MrfProblem& problem, const AlphaExpansionOptions& options) {
    detail::checkMrfProblem(problem);
    MrfSolution solution;
    solution.labels = mrfArgmin(problem);
    solution.initial_energy = mrfEnergy(problem, solution.labels);
    if (problem.lambda == 0.0 || problem.num_nodes == 0 || problem.edges.empty()) {
        // Without smoothness the per-node argmin is the exact minimum.
        solution.final_energy = solution.initial_energy;
        return solution;
    }
    const Adjacency adj = buildAdjacency(problem);
    const Components comps = findComponents(problem, adj);
    const std::size_t num_components = comps.offsets.size() - 1;
    std::vector<std::int32_t> local_of(problem.num_nodes, -1);
    std::vector<int> sweeps(num_components, 0);
    const int max_sweeps = std::max(1, options.max_sweeps);
    auto solveOne = [&](std::size_t c) {
        const std::uint64_t b = comps.offsets[c];
        const std::size_t size = comps.offsets[c + 1] - b;
        if (size < 2) return;  // a lone node keeps its argmin
        ComponentSolver solver(problem, adj, comps.nodes.data() + b, size, solution.labels,
                               local_of);
        sweeps[c] = solver.solve(max_sweeps);
    };
    // Components share no edge, so solving them in any order gives the same labelling.
    if (options.parallel_components) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, num_components, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t c = r.begin(); c != r.end(); ++c) solveOne(c);
                          });
    } else {
        for (std::size_t c = 0; c < num_components; ++c) solveOne(c);
    }
    solution.sweeps = sweeps.empty() ? 0 : *std::max_element(sweeps.begin(), sweeps.end());
    solution.final_energy = mrfEnergy(problem, solution.labels);
    std::ostringstream msg;
    msg << "alpha-expansion: " << problem.num_nodes << " nodes, " << problem.edges.size()
        << " edges, " << num_components << " components, energy " << solution.initial_energy
        << " -> " << solution.final_energy << " in " << solution.sweeps << " sweep(s)";
    logInfo(msg.str());
    return solution;
}

}  // namespace vdbmap
