// SPDX-License-Identifier: Apache-2.0
// BinaryCut (the minimum cut of an alpha-expansion move) against exhaustive search: on random
// graph-representable energies of up to 14 variables, the labelling it returns has the least
// energy of all 2^n labellings, and solve() returns that energy.
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <vector>

#include "mrf/BinaryCut.h"

using vdbmap::detail::BinaryCut;

namespace {

struct Energy {
    std::vector<double> cost0, cost1;
    struct Pair {
        std::size_t v, u;
        double c;
    };
    std::vector<Pair> pairs;

    double operator()(const std::vector<char>& x) const {
        double e = 0.0;
        for (std::size_t v = 0; v < cost0.size(); ++v) e += x[v] ? cost1[v] : cost0[v];
        for (const Pair& p : pairs) e += (!x[p.v] && x[p.u]) ? p.c : 0.0;
        return e;
    }
};

Energy randomEnergy(std::mt19937& rng, std::size_t n, std::size_t num_pairs) {
    std::uniform_real_distribution<double> unary(-2.0, 3.0), pair(0.0, 2.5);
    std::uniform_int_distribution<std::size_t> var(0, n - 1);
    Energy e;
    for (std::size_t v = 0; v < n; ++v) {
        e.cost0.push_back(unary(rng));
        e.cost1.push_back(unary(rng));
    }
    for (std::size_t k = 0; k < num_pairs; ++k) {
        const std::size_t v = var(rng), u = var(rng);
        if (v != u) e.pairs.push_back({v, u, pair(rng)});
    }
    return e;
}

double bruteForceMinimum(const Energy& e) {
    const std::size_t n = e.cost0.size();
    double best = 1e300;
    std::vector<char> x(n);
    for (std::uint32_t bits = 0; bits < (1u << n); ++bits) {
        for (std::size_t v = 0; v < n; ++v) x[v] = (bits >> v) & 1u;
        best = std::min(best, e(x));
    }
    return best;
}

}  // namespace

TEST_CASE("BinaryCut finds the minimum of random binary energies", "[mrf]") {
    std::mt19937 rng(7);
    BinaryCut cut;
    std::vector<char> x;
    int instances = 0;
    for (std::size_t n : {1, 2, 3, 5, 8, 11, 14}) {
        for (std::size_t density : {0, 1, 2, 4}) {
            for (int trial = 0; trial < 60; ++trial) {
                const Energy e = randomEnergy(rng, n, density * n);
                cut.reset(n);
                for (std::size_t v = 0; v < n; ++v) cut.addUnary(v, e.cost0[v], e.cost1[v]);
                for (const auto& p : e.pairs) cut.addPair(p.v, p.u, p.c);
                const double value = cut.solve(x);
                const double best = bruteForceMinimum(e);
                REQUIRE(x.size() == n);
                INFO("n = " << n << ", pairs = " << e.pairs.size() << ", trial " << trial);
                CHECK(e(x) == Approx(best).margin(1e-9));
                CHECK(value == Approx(best).margin(1e-9));
                ++instances;
            }
        }
    }
    CHECK(instances == 7 * 4 * 60);
}

TEST_CASE("BinaryCut on a chain: the cut is where the unaries change sides", "[mrf]") {
    // x_0 prefers 0 strongly, x_9 prefers 1 strongly, the others are indifferent; pairs
    // c [x_v = 0 and x_{v+1} = 1] with the cheapest at 6 -> 7: the minimum cuts there.
    BinaryCut cut;
    cut.reset(10);
    cut.addUnary(0, 0.0, 100.0);
    cut.addUnary(9, 100.0, 0.0);
    for (std::size_t v = 0; v + 1 < 10; ++v) cut.addPair(v, v + 1, v == 6 ? 1.0 : 5.0);
    std::vector<char> x;
    CHECK(cut.solve(x) == Approx(1.0));
    CHECK(x == std::vector<char>{0, 0, 0, 0, 0, 0, 0, 1, 1, 1});
}
