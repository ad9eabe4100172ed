// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <random>

#include "vdbmap/core/Log.h"
#include "vdbmap/mrf/PottsMrf.h"

using vdbmap::kNoLabel;
using vdbmap::MrfProblem;

namespace {

// Random sparse problem: each node gets a random subset of labels (possibly empty) with
// non-negative costs, random edges with positive weights.
MrfProblem randomProblem(std::mt19937& rng, std::size_t n, std::size_t num_labels,
                         std::size_t num_edges, bool allow_empty) {
    std::uniform_real_distribution<float> cost(0.0f, 3.0f);
    std::uniform_real_distribution<float> weight(0.1f, 2.0f);
    std::bernoulli_distribution take(0.6);
    MrfProblem p;
    p.num_nodes = n;
    p.num_labels = num_labels;
    p.offsets.push_back(0);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::uint32_t l = 0; l < num_labels; ++l) {
            if (take(rng)) {
                p.cand_labels.push_back(l);
                p.cand_costs.push_back(cost(rng));
            }
        }
        if (!allow_empty && p.cand_labels.size() == p.offsets.back()) {
            p.cand_labels.push_back(static_cast<std::uint32_t>(i % num_labels));
            p.cand_costs.push_back(cost(rng));
        }
        p.offsets.push_back(p.cand_labels.size());
    }
    std::uniform_int_distribution<std::uint32_t> node(0, static_cast<std::uint32_t>(n - 1));
    while (p.edges.size() < num_edges) {
        const std::uint32_t a = node(rng), b = node(rng);
        if (a == b) continue;
        p.edges.push_back({std::min(a, b), std::max(a, b)});
        p.edge_weights.push_back(weight(rng));
    }
    return p;
}

// The candidate labels of node i, plus every label for a free empty node.
std::vector<std::uint32_t> choices(const MrfProblem& p, std::size_t i) {
    std::vector<std::uint32_t> c(p.cand_labels.begin() + static_cast<long>(p.offsets[i]),
                                 p.cand_labels.begin() + static_cast<long>(p.offsets[i + 1]));
    if (c.empty()) {
        if (p.empty_nodes_free) {
            for (std::uint32_t l = 0; l < p.num_labels; ++l) c.push_back(l);
        } else {
            c.push_back(kNoLabel);
        }
    }
    return c;
}

// Exhaustive minimum over all labellings (oracle for tiny problems).
double bruteForceMinimum(const MrfProblem& p) {
    std::vector<std::vector<std::uint32_t>> options;
    for (std::size_t i = 0; i < p.num_nodes; ++i) options.push_back(choices(p, i));
    std::vector<std::size_t> idx(p.num_nodes, 0);
    std::vector<std::uint32_t> labels(p.num_nodes);
    double best = std::numeric_limits<double>::infinity();
    while (true) {
        for (std::size_t i = 0; i < p.num_nodes; ++i) labels[i] = options[i][idx[i]];
        best = std::min(best, vdbmap::mrfEnergy(p, labels));
        std::size_t k = 0;
        while (k < p.num_nodes && ++idx[k] == options[k].size()) idx[k++] = 0;
        if (k == p.num_nodes) break;
    }
    return best;
}

// Best energy reachable from `labels` by one expansion move for any alpha (exhaustive).
double bestExpansionMove(const MrfProblem& p, const std::vector<std::uint32_t>& labels) {
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t alpha = 0; alpha < p.num_labels; ++alpha) {
        std::vector<std::size_t> movable;
        for (std::size_t i = 0; i < p.num_nodes; ++i) {
            const auto c = choices(p, i);
            if (labels[i] != alpha && std::find(c.begin(), c.end(), alpha) != c.end()) {
                movable.push_back(i);
            }
        }
        for (std::uint64_t mask = 0; mask < (std::uint64_t(1) << movable.size()); ++mask) {
            auto moved = labels;
            for (std::size_t k = 0; k < movable.size(); ++k) {
                if (mask >> k & 1) moved[movable[k]] = alpha;
            }
            best = std::min(best, vdbmap::mrfEnergy(p, moved));
        }
    }
    return best;
}

}  // namespace

TEST_CASE("alpha-expansion reaches an expansion-move local minimum within 2x of optimal",
          "[mrf]") {
    vdbmap::setLogLevel(vdbmap::LogLevel::Warn);
    std::mt19937 rng(7);
    for (int trial = 0; trial < 60; ++trial) {
        const bool free_empty = trial % 3 == 0;
        MrfProblem p = randomProblem(rng, 7, 3, 10, true);
        p.empty_nodes_free = free_empty;
        p.lambda = 0.25 + 0.5 * (trial % 4);
        const auto sol = vdbmap::solveAlphaExpansion(p);
        INFO("trial " << trial);
        REQUIRE(sol.final_energy <= sol.initial_energy + 1e-9);
        REQUIRE(sol.final_energy == Approx(vdbmap::mrfEnergy(p, sol.labels)));
        const double optimum = bruteForceMinimum(p);
        REQUIRE(sol.final_energy >= optimum - 1e-6);
        // Boykov-Veksler-Zabih bound for Potts with non-negative data costs.
        REQUIRE(sol.final_energy <= 2.0 * optimum + 1e-6);
        // No single expansion move improves the result: the max-flow cuts were optimal.
        REQUIRE(bestExpansionMove(p, sol.labels) >= sol.final_energy - 1e-5);
        for (std::size_t i = 0; i < p.num_nodes; ++i) {
            const auto c = choices(p, i);
            REQUIRE(std::find(c.begin(), c.end(), sol.labels[i]) != c.end());
        }
    }
}

TEST_CASE("lambda = 0 returns the per-node argmin", "[mrf]") {
    std::mt19937 rng(3);
    MrfProblem p = randomProblem(rng, 500, 6, 1500, false);
    p.lambda = 0.0;
    const auto sol = vdbmap::solveAlphaExpansion(p);
    REQUIRE(sol.labels == vdbmap::mrfArgmin(p));
    REQUIRE(sol.final_energy == sol.initial_energy);
}

TEST_CASE("alpha-expansion denoises a two-region grid and never raises the energy", "[mrf]") {
    // 60 x 60 grid, left half class 0 and right half class 1, 20 % of the nodes with the wrong
    // unary preference. Strong smoothness recovers the two regions up to the rare noise
    // clusters that the energy itself prefers (the truth is no better than the result).
    const std::uint32_t n = 60;
    std::mt19937 rng(11);
    std::bernoulli_distribution flip(0.2);
    MrfProblem p;
    p.num_nodes = n * n;
    p.num_labels = 3;
    p.offsets.push_back(0);
    std::size_t wrong_argmin = 0;
    for (std::uint32_t y = 0; y < n; ++y) {
        for (std::uint32_t x = 0; x < n; ++x) {
            const std::uint32_t truth = x < n / 2 ? 0 : 1;
            const bool noisy = flip(rng);
            wrong_argmin += noisy;
            for (std::uint32_t l = 0; l < 3; ++l) {
                p.cand_labels.push_back(l);
                const bool preferred = noisy ? l == 2 : l == truth;
                p.cand_costs.push_back(preferred ? 0.1f : 1.0f);
            }
            p.offsets.push_back(p.cand_labels.size());
            if (x + 1 < n) p.edges.push_back({y * n + x, y * n + x + 1});
            if (y + 1 < n) p.edges.push_back({y * n + x, (y + 1) * n + x});
        }
    }
    p.lambda = 0.6;
    const auto sol = vdbmap::solveAlphaExpansion(p);
    REQUIRE(wrong_argmin > 500);
    REQUIRE(sol.final_energy < sol.initial_energy);
    std::size_t wrong = 0;
    std::vector<std::uint32_t> truth(p.num_nodes);
    for (std::uint32_t y = 0; y < n; ++y) {
        for (std::uint32_t x = 0; x < n; ++x) {
            truth[y * n + x] = x < n / 2 ? 0u : 1u;
            wrong += sol.labels[y * n + x] != truth[y * n + x];
        }
    }
    REQUIRE(sol.final_energy <= vdbmap::mrfEnergy(p, truth) + 1e-6);
    REQUIRE(wrong < p.num_nodes / 100);
}

TEST_CASE("parallel components give the same labelling as serial", "[mrf]") {
    std::mt19937 rng(5);
    // Many small disjoint random problems glued into one.
    MrfProblem p;
    p.num_labels = 5;
    p.offsets.push_back(0);
    for (int block = 0; block < 200; ++block) {
        const MrfProblem b = randomProblem(rng, 12, 5, 20, true);
        const auto base = static_cast<std::uint32_t>(p.num_nodes);
        for (std::size_t i = 0; i < b.num_nodes; ++i) {
            for (auto k = b.offsets[i]; k < b.offsets[i + 1]; ++k) {
                p.cand_labels.push_back(b.cand_labels[k]);
                p.cand_costs.push_back(b.cand_costs[k]);
            }
            p.offsets.push_back(p.cand_labels.size());
        }
        for (std::size_t e = 0; e < b.edges.size(); ++e) {
            p.edges.push_back({b.edges[e][0] + base, b.edges[e][1] + base});
            p.edge_weights.push_back(b.edge_weights[e]);
        }
        p.num_nodes += b.num_nodes;
    }
    vdbmap::AlphaExpansionOptions serial;
    serial.parallel_components = false;
    const auto a = vdbmap::solveAlphaExpansion(p, serial);
    const auto b = vdbmap::solveAlphaExpansion(p);
    REQUIRE(a.labels == b.labels);
    REQUIRE(a.final_energy == b.final_energy);
    REQUIRE(a.final_energy <= a.initial_energy);
    // Nodes without candidates stay unlabelled when empty nodes are not free.
    for (std::size_t i = 0; i < p.num_nodes; ++i) {
        if (p.offsets[i] == p.offsets[i + 1]) REQUIRE(a.labels[i] == kNoLabel);
    }
}
