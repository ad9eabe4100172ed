// SPDX-License-Identifier: Apache-2.0
// LeafNeighbourhood (map/LeafNeighbourhood.h): the bits of a box of leaves as the AND of three
// precomputed slabs (markBox) against the plain triple loop over the box, for every
// neighbourhood size the integrator uses (radius 1 to 3: 1, 2 and 6 words of bits).
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <vector>

#include "map/LeafNeighbourhood.h"

using vdbmap::detail::LeafNeighbourhood;

namespace {

std::vector<std::uint64_t> loopBox(const LeafNeighbourhood& hood, int x0, int x1, int y0, int y1,
                                   int z0, int z1) {
    std::vector<std::uint64_t> bits(hood.words, 0);
    for (int x = x0; x <= x1; ++x)
        for (int y = y0; y <= y1; ++y)
            for (int z = z0; z <= z1; ++z) {
                const std::size_t b = hood.bit(x, y, z);
                bits[b / 64] |= std::uint64_t{1} << (b % 64);
            }
    return bits;
}

}  // namespace

TEST_CASE("LeafNeighbourhood::markBox sets exactly the leaves of the box", "[tsdf][leaves]") {
    std::mt19937 rng(7);
    for (const int reach_vox : {5, 10, 20}) {
        const LeafNeighbourhood hood(reach_vox);
        const int r = hood.radius;
        INFO("reach " << reach_vox << " voxels: radius " << r << ", " << hood.words << " words");
        CHECK(hood.words == (static_cast<std::size_t>(hood.side) * hood.side * hood.side + 63) / 64);
        std::uniform_int_distribution<int> coord(-r, r);
        for (int trial = 0; trial < 2000; ++trial) {
            int x0 = coord(rng), x1 = coord(rng), y0 = coord(rng), y1 = coord(rng), z0 = coord(rng),
                z1 = coord(rng);
            // Every fourth box is left unordered on one axis: an empty box sets nothing.
            if (trial % 4 != 0) {
                if (x0 > x1) std::swap(x0, x1);
                if (y0 > y1) std::swap(y0, y1);
                if (z0 > z1) std::swap(z0, z1);
            }
            // The bits already set stay set (markBox ORs into them).
            std::vector<std::uint64_t> bits(hood.words, 0);
            bits[0] |= 1u;
            hood.markBox(bits.data(), x0, x1, y0, y1, z0, z1);
            std::vector<std::uint64_t> expected = loopBox(hood, x0, x1, y0, y1, z0, z1);
            expected[0] |= 1u;
            REQUIRE(bits == expected);
        }
        // The whole neighbourhood: every one of side^3 bits, none beyond.
        std::vector<std::uint64_t> all(hood.words, 0);
        hood.markBox(all.data(), -r, r, -r, r, -r, r);
        std::size_t set = 0;
        for (const std::uint64_t w : all) set += static_cast<std::size_t>(__builtin_popcountll(w));
        CHECK(set == hood.size());
    }
}
