// SPDX-License-Identifier: Apache-2.0
#include "SemanticFusion.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/core/UnionFind.h"

namespace vdbmap::semantic {

MrfProblem fusionProblem(const FaceVotes& votes,
                         const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                         const FusionOptions& options) {
    const std::size_t num_faces = votes.numFaces();
    const std::size_t n = votes.num_classes;
    MrfProblem problem;
    problem.num_nodes = num_faces;
    problem.num_labels = n;
    problem.lambda = options.lambda;
    problem.edges = adjacency;
    if (options.edge_weights != nullptr) {
        if (options.edge_weights->size() != adjacency.size()) {
            throw InvalidInput("semantic fusion: " + std::to_string(options.edge_weights->size()) +
                               " edge weights for " + std::to_string(adjacency.size()) + " edges");
        }
        problem.edge_weights = *options.edge_weights;
    }
    problem.offsets.reserve(num_faces + 1);
    problem.offsets.push_back(0);
    const double floor = std::max(options.probability_floor, 1e-12);
    const auto floor_cost = static_cast<float>(-std::log(floor));
    // Paper: a face no view saw starts from the uniform distribution 1/N.
    const auto uniform_cost = static_cast<float>(-std::log(1.0 / static_cast<double>(n)));

    // Regions of unobserved faces and the classes voted on their border. Inside a region
    // without data the Potts optimum only uses border classes (relabelling a non-border class
    // to a neighbouring one never lengthens the cut), so those are the only candidates needed:
    // this keeps every expansion move small.
    std::vector<std::uint32_t> region = makeDisjointSets(num_faces);
    for (const auto& e : adjacency) {
        if (votes.observed(e[0]) || votes.observed(e[1])) continue;
        uniteSets(region, e[0], e[1]);
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> border;  // (region root, class)
    for (const auto& e : adjacency) {
        const bool o0 = votes.observed(e[0]), o1 = votes.observed(e[1]);
        if (o0 == o1) continue;
        const std::uint32_t u = o0 ? e[1] : e[0];
        const std::uint32_t o = o0 ? e[0] : e[1];
        const std::uint32_t root = findRoot(region, u);
        for (std::uint64_t k = votes.offsets[o]; k < votes.offsets[o + 1]; ++k) {
            border.emplace_back(root, votes.classes[k]);
        }
    }
    std::sort(border.begin(), border.end());
    border.erase(std::unique(border.begin(), border.end()), border.end());

    for (std::size_t f = 0; f < num_faces; ++f) {
        const std::uint64_t b = votes.offsets[f];
        const std::uint64_t e = votes.offsets[f + 1];
        if (b == e) {
            const std::uint32_t root = findRoot(region, static_cast<std::uint32_t>(f));
            auto it = std::lower_bound(border.begin(), border.end(),
                                       std::make_pair(root, std::uint32_t(0)));
            if (it == border.end() || it->first != root) {
                // No observed face anywhere around: fuseLabels writes 255, any class will do.
                problem.cand_labels.push_back(0);
                problem.cand_costs.push_back(uniform_cost);
            }
            for (; it != border.end() && it->first == root; ++it) {
                problem.cand_labels.push_back(it->second);
                problem.cand_costs.push_back(uniform_cost);
            }
        } else {
            // Paper Eq. (semantic_mrf_energy_function): accumulated areas normalised over the
            // classes; the cost is its negative log with a floor.
            double total = 0.0;
            for (std::uint64_t k = b; k < e; ++k) total += votes.weights[k];
            std::uint64_t k = b;
            for (std::uint32_t c = 0; c < n; ++c) {
                const bool voted = k < e && votes.classes[k] == c;
                if (voted) {
                    const double p = total > 0.0 ? votes.weights[k] / total
                                                 : 1.0 / static_cast<double>(e - b);
                    problem.cand_labels.push_back(c);
                    problem.cand_costs.push_back(
                        static_cast<float>(-std::log(std::max(p, floor))));
                    ++k;
                } else if (options.all_classes) {
                    problem.cand_labels.push_back(c);
                    problem.cand_costs.push_back(floor_cost);
                }
            }
        }
        problem.offsets.push_back(problem.cand_labels.size());
    }
    return problem;
}

namespace {

std::vector<float> posteriorMargins(const FaceVotes& votes, const std::vector<std::uint32_t>& cls,
                                    const std::vector<std::uint8_t>& face_labels) {
    std::vector<float> margin(votes.numFaces(), 0.0f);
    for (std::size_t f = 0; f < margin.size(); ++f) {
        if (!votes.observed(f) || face_labels[f] == kUnknownLabel) continue;
        double total = 0.0, own = 0.0, other = 0.0;
        for (std::uint64_t k = votes.offsets[f]; k < votes.offsets[f + 1]; ++k) {
            total += votes.weights[k];
            if (votes.classes[k] == cls[f]) {
                own = votes.weights[k];
            } else {
                other = std::max(other, static_cast<double>(votes.weights[k]));
            }
        }
        if (total > 0.0) margin[f] = static_cast<float>(std::max(0.0, (own - other) / total));
    }
    return margin;
}

}  // namespace

FusionResult fuseLabels(const FaceVotes& votes,
                        const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                        const LabelSet& labels, const FusionOptions& options) {
    const std::size_t num_faces = votes.numFaces();
    if (votes.num_classes != labels.size()) {
        throw InvalidInput("semantic fusion: votes over " + std::to_string(votes.num_classes) +
                           " classes but the label set has " + std::to_string(labels.size()));
    }
    if (labels.size() == 0) throw InvalidInput("semantic fusion: the label set is empty");
    for (const auto& e : adjacency) {
        if (e[0] >= num_faces || e[1] >= num_faces) {
            throw InvalidInput("semantic fusion: adjacency pair (" + std::to_string(e[0]) + ", " +
                               std::to_string(e[1]) + ") is out of range for " +
                               std::to_string(num_faces) + " faces");
        }
    }
    FusionResult result;
    result.face_labels.assign(num_faces, kUnknownLabel);
    if (num_faces == 0) return result;

    const MrfProblem problem = fusionProblem(votes, adjacency, options);
    AlphaExpansionOptions solver;
    solver.max_sweeps = options.max_sweeps;
    const MrfSolution solution = solveAlphaExpansion(problem, solver);
    result.initial_energy = solution.initial_energy;
    result.final_energy = solution.final_energy;
    result.sweeps = solution.sweeps;

    // Components without any observed face have nothing to take a class from.
    std::vector<std::uint32_t> parent = makeDisjointSets(num_faces);
    for (const auto& e : adjacency) uniteSets(parent, e[0], e[1]);
    std::vector<char> root_observed(num_faces, 0);
    for (std::size_t f = 0; f < num_faces; ++f) {
        if (votes.observed(f)) root_observed[findRoot(parent, static_cast<std::uint32_t>(f))] = 1;
    }
    for (std::size_t f = 0; f < num_faces; ++f) {
        const std::uint32_t root = findRoot(parent, static_cast<std::uint32_t>(f));
        const bool observed = votes.observed(f);
        result.observed_faces += observed;
        if (root == f && !root_observed[root]) ++result.unlabelled_components;
        // lambda = 0 is naive voting: an unobserved face stays unknown.
        const bool labelled = observed || (root_observed[root] && options.lambda > 0.0);
        if (!labelled) {
            ++result.unlabelled_faces;
            continue;
        }
        result.filled_faces += !observed;
        result.face_labels[f] = labels.classes()[solution.labels[f]].id;
    }
    result.confidence = posteriorMargins(votes, solution.labels, result.face_labels);
    return result;
}

}  // namespace vdbmap::semantic
