// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <random>

#include "TextureTestScenes.h"
#include "ViewSelection.h"

using namespace vdbmap::texture;
using namespace vdbmap::texture::test;
using vdbmap::kNoLabel;

namespace {

/// A 12 x 6 plane grid; view 0 sees every face, views 1..3 random subsets; random qualities.
struct Scene {
    MeshArrays mesh = planeGrid(12, 6, 2.0f, 1.0f, 5.0f);
    std::vector<vdbmap::View> views = {makeView(0, 0.0), makeView(1, 0.2), makeView(2, -0.2),
                                       makeView(3, 0.4)};
    vdbmap::Visibility vis;
    std::vector<ObservationStats> stats;
    std::vector<std::array<std::uint32_t, 2>> adjacency;

    explicit Scene(unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> uni(0.0f, 1.0f);
        std::vector<std::vector<char>> sees(mesh.faces.size(), std::vector<char>(4, 0));
        for (auto& s : sees) {
            s[0] = 1;
            for (int v = 1; v < 4; ++v) s[v] = uni(rng) < 0.6f;
        }
        vis =
            makeVisibility(mesh, views, [&](std::size_t f, std::uint32_t v) { return sees[f][v]; });
        stats.resize(vis.obs.size());
        for (auto& s : stats) s.quality = 10.0f + 100.0f * uni(rng);
        adjacency = bruteAdjacency(mesh);
    }
};

}  // namespace

TEST_CASE("data cost is 0 for the best view and 1 - E_Q / max otherwise", "[texture][mrf]") {
    Scene scene(1);
    const std::vector<char> keep(scene.vis.obs.size(), 1);
    const auto problem =
        buildViewSelectionProblem(scene.vis, scene.stats, keep, scene.adjacency, 4, 1.0);
    REQUIRE(problem.num_nodes == scene.mesh.faces.size());
    for (std::size_t f = 0; f < problem.num_nodes; ++f) {
        float best = 0;
        for (auto i = scene.vis.offsets[f]; i < scene.vis.offsets[f + 1]; ++i) {
            best = std::max(best, scene.stats[i].quality);
        }
        for (auto i = scene.vis.offsets[f]; i < scene.vis.offsets[f + 1]; ++i) {
            const auto k = problem.offsets[f] + (i - scene.vis.offsets[f]);
            CHECK(problem.cand_labels[k] == scene.vis.obs[i].view);
            CHECK(problem.cand_costs[k] == Approx(1.0f - scene.stats[i].quality / best));
        }
    }
}

TEST_CASE("lambda = 0 reproduces the per-face best view", "[texture][mrf]") {
    for (unsigned seed : {1u, 2u, 3u}) {
        Scene scene(seed);
        const std::vector<char> keep(scene.vis.obs.size(), 1);
        const auto problem =
            buildViewSelectionProblem(scene.vis, scene.stats, keep, scene.adjacency, 4, 0.0);
        const auto solution = selectViews(problem, true);
        for (std::size_t f = 0; f < scene.mesh.faces.size(); ++f) {
            std::uint32_t best_view = kNoLabel;
            float best = -1;
            for (auto i = scene.vis.offsets[f]; i < scene.vis.offsets[f + 1]; ++i) {
                if (scene.stats[i].quality > best) {
                    best = scene.stats[i].quality;
                    best_view = scene.vis.obs[i].view;
                }
            }
            CHECK(solution.labels[f] == best_view);
        }
    }
}

TEST_CASE("large lambda on a plane fully seen by one view picks that view", "[texture][mrf]") {
    Scene scene(5);
    const std::vector<char> keep(scene.vis.obs.size(), 1);
    const auto problem =
        buildViewSelectionProblem(scene.vis, scene.stats, keep, scene.adjacency, 4, 1000.0);
    const auto solution = selectViews(problem, true);
    for (std::uint32_t label : solution.labels) CHECK(label == 0u);
    CHECK(solution.final_energy < solution.initial_energy);
}

TEST_CASE("view selection energy never rises", "[texture][mrf]") {
    for (double lambda : {0.1, 0.5, 1.0, 3.0}) {
        Scene scene(static_cast<unsigned>(lambda * 10));
        const std::vector<char> keep(scene.vis.obs.size(), 1);
        const auto problem =
            buildViewSelectionProblem(scene.vis, scene.stats, keep, scene.adjacency, 4, lambda);
        const auto best = selectViews(problem, false);
        const auto mrf = selectViews(problem, true);
        CHECK(mrf.initial_energy == Approx(best.final_energy));
        CHECK(mrf.final_energy <= mrf.initial_energy + 1e-9);
        CHECK(vdbmap::mrfEnergy(problem, mrf.labels) == Approx(mrf.final_energy));
    }
}

TEST_CASE("rejected observations are no candidates; unseen faces get no label", "[texture][mrf]") {
    Scene scene(9);
    std::vector<char> keep(scene.vis.obs.size(), 1);
    // Face 0 loses all its observations.
    for (auto i = scene.vis.offsets[0]; i < scene.vis.offsets[1]; ++i) keep[i] = 0;
    const auto problem =
        buildViewSelectionProblem(scene.vis, scene.stats, keep, scene.adjacency, 4, 1.0);
    CHECK(problem.offsets[1] == 0);
    const auto solution = selectViews(problem, true);
    CHECK(solution.labels[0] == kNoLabel);
    CHECK(solution.labels[1] != kNoLabel);
}

TEST_CASE("max_candidates keeps the views of highest quality", "[texture][mrf]") {
    Scene scene(13);
    const std::vector<char> keep(scene.vis.obs.size(), 1);
    const auto problem =
        buildViewSelectionProblem(scene.vis, scene.stats, keep, scene.adjacency, 4, 0.0, 2);
    const auto all =
        buildViewSelectionProblem(scene.vis, scene.stats, keep, scene.adjacency, 4, 0.0, 0);
    for (std::size_t f = 0; f < problem.num_nodes; ++f) {
        const auto n = problem.offsets[f + 1] - problem.offsets[f];
        const auto n_all = all.offsets[f + 1] - all.offsets[f];
        CHECK(n == std::min<std::uint64_t>(n_all, 2));
        // The kept candidates are the cheapest of all (cost = 1 - E_Q / max).
        std::vector<float> costs(all.cand_costs.begin() + all.offsets[f],
                                 all.cand_costs.begin() + all.offsets[f + 1]);
        std::sort(costs.begin(), costs.end());
        for (auto k = problem.offsets[f]; k < problem.offsets[f + 1]; ++k) {
            CHECK(problem.cand_costs[k] <= costs[std::min<std::size_t>(1, costs.size() - 1)]);
        }
    }
    CHECK(selectViews(problem, true).labels == selectViews(all, false).labels);
}
