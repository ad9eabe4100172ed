// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <cmath>

#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"

using vdbmap::kNoLabel;
using vdbmap::MrfProblem;

namespace {

// Three nodes in a chain 0 - 1 - 2; node 1 has no candidates.
MrfProblem chainWithEmptyMiddle() {
    MrfProblem p;
    p.num_nodes = 3;
    p.num_labels = 3;
    p.offsets = {0, 2, 2, 4};
    p.cand_labels = {0, 2, 1, 2};
    p.cand_costs = {1.0f, 0.5f, 0.25f, 2.0f};
    p.edges = {{0, 1}, {1, 2}, {0, 2}};
    p.edge_weights = {1.0f, 2.0f, 4.0f};
    p.lambda = 0.5;
    return p;
}

}  // namespace

TEST_CASE("mrfArgmin takes the cheapest candidate, ties to the smaller label", "[mrf]") {
    MrfProblem p = chainWithEmptyMiddle();
    auto labels = vdbmap::mrfArgmin(p);
    REQUIRE(labels == std::vector<std::uint32_t>{2, kNoLabel, 1});
    p.cand_costs = {0.5f, 0.5f, 3.0f, 3.0f};
    labels = vdbmap::mrfArgmin(p);
    REQUIRE(labels == std::vector<std::uint32_t>{0, kNoLabel, 1});
    p.empty_nodes_free = true;
    labels = vdbmap::mrfArgmin(p);
    REQUIRE(labels[1] == 0);
}

TEST_CASE("mrfEnergy sums unaries and weighted Potts cuts", "[mrf]") {
    MrfProblem p = chainWithEmptyMiddle();
    // kNoLabel node costs nothing and cuts no edge; only edge (0,2) counts.
    REQUIRE(vdbmap::mrfEnergy(p, {2, kNoLabel, 1}) == Approx(0.5 + 0.25 + 0.5 * 4.0));
    REQUIRE(vdbmap::mrfEnergy(p, {2, kNoLabel, 2}) == Approx(0.5 + 2.0));
    // A label that is not a candidate is infinitely expensive.
    REQUIRE(std::isinf(vdbmap::mrfEnergy(p, {1, kNoLabel, 2})));
    p.empty_nodes_free = true;
    REQUIRE(vdbmap::mrfEnergy(p, {2, 0, 2}) == Approx(0.5 + 2.0 + 0.5 * (1.0 + 2.0)));
}

TEST_CASE("inconsistent MRF problems are rejected", "[mrf]") {
    MrfProblem p = chainWithEmptyMiddle();
    SECTION("label out of range") {
        p.cand_labels[0] = 7;
        REQUIRE_THROWS_AS(vdbmap::mrfArgmin(p), vdbmap::InvalidInput);
    }
    SECTION("offsets of the wrong size") {
        p.offsets.pop_back();
        REQUIRE_THROWS_AS(vdbmap::solveAlphaExpansion(p), vdbmap::InvalidInput);
    }
    SECTION("self edge") {
        p.edges[0] = {1, 1};
        REQUIRE_THROWS_WITH(vdbmap::solveAlphaExpansion(p),
                            Catch::Contains("self edge"));
    }
    SECTION("negative weight") {
        p.edge_weights[2] = -1.0f;
        REQUIRE_THROWS_AS(vdbmap::solveAlphaExpansion(p), vdbmap::InvalidInput);
    }
    SECTION("labelling of the wrong size") {
        REQUIRE_THROWS_AS(vdbmap::mrfEnergy(p, {0, 0}), vdbmap::InvalidInput);
    }
}
