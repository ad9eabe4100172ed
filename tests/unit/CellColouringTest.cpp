// SPDX-License-Identifier: Apache-2.0
// Phase 3's schedule: cells of one colour run in parallel, so two different cells of one colour
// must be far enough apart that no voxel update of one reaches a leaf the other writes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <vector>

#include "map/CellColouring.h"

using namespace vdbmap::detail;
using openvdb::Coord;

TEST_CASE("cells of one colour keep their update neighbourhoods apart, and the 8 colours run apart",
          "[tsdf][determinism]") {
    for (int radius : {1, 2}) {  // the leaf neighbourhood radius R, in blocks
        const int cell_blocks = 2 * radius;  // as the integrator
        std::vector<std::pair<Coord, CellKey>> blocks;
        for (int x = -7; x <= 7; ++x)
            for (int y = -7; y <= 7; ++y)
                for (int z = -7; z <= 7; ++z) {
                    const Coord b(x, y, z);
                    blocks.emplace_back(b, cellKeyOf(b, cell_blocks));
                }
        std::set<std::uint32_t> colours;
        for (const auto& [b, key] : blocks) {
            REQUIRE(key.colour < 8);
            colours.insert(key.colour);
            const Coord cell(floorDiv(b.x(), cell_blocks), floorDiv(b.y(), cell_blocks),
                             floorDiv(b.z(), cell_blocks));
            CHECK(key == cellKeyOf(Coord(cell.x() * cell_blocks, cell.y() * cell_blocks,
                                         cell.z() * cell_blocks), cell_blocks));
        }
        CHECK(colours.size() == 8);
        // Same colour, other cell: on some axis the blocks are more than 2 R apart, so their
        // neighbourhoods (R blocks around each: what its updates can write) do not meet.
        for (std::size_t i = 0; i < blocks.size(); i += 7)
            for (std::size_t j = 0; j < blocks.size(); ++j) {
                const auto& [a, ka] = blocks[i];
                const auto& [b, kb] = blocks[j];
                if (ka.colour != kb.colour || ka.cell == kb.cell) continue;
                const int d = std::max({std::abs(a.x() - b.x()), std::abs(a.y() - b.y()),
                                        std::abs(a.z() - b.z())});
                REQUIRE(d >= 2 * radius + 1);
            }
        // Sorted, the schedule visits colour after colour: each colour is one contiguous run.
        std::vector<CellKey> keys;
        for (const auto& bk : blocks) keys.push_back(bk.second);
        std::sort(keys.begin(), keys.end());
        std::size_t runs = 1;
        for (std::size_t i = 1; i < keys.size(); ++i) runs += keys[i].colour != keys[i - 1].colour;
        CHECK(runs == 8);
    }
}
