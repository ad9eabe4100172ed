// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/Types.h>

#include <cstdint>

namespace vdbmap::detail {

inline int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

/// The phase-3 schedule key of a block: its cell (cubes of `cell_blocks`^3 blocks) and the
/// cell's colour (cx mod 2, cy mod 2, cz mod 2) as 0..7. With cells 2 R blocks wide, where R is
/// the radius (blocks) of the leaf neighbourhood a block's updates can reach, two different cells
/// of one colour leave a gap of at least 2 R blocks on some axis, so the neighbourhoods of their
/// blocks are disjoint and the cells of one colour can be integrated in parallel (8 colours, one
/// after another). The colour is its own field: an earlier packing above the cell's 60 bits lost
/// colour bits and ran adjacent cells at the same time.
struct CellKey {
    std::uint32_t colour = 0;  ///< 0..7
    std::uint64_t cell = 0;    ///< 20 bits per axis; cells 2^20 apart share a key (one task: safe)

    bool operator==(const CellKey& o) const { return colour == o.colour && cell == o.cell; }
    bool operator!=(const CellKey& o) const { return !(*this == o); }
    /// Colour first: the colours run one after another.
    bool operator<(const CellKey& o) const {
        return colour != o.colour ? colour < o.colour : cell < o.cell;
    }
    /// The key as one number (colour above the cell's 60 bits), in operator<'s order.
    std::uint64_t packed() const { return (static_cast<std::uint64_t>(colour) << 60) | cell; }
};

inline CellKey cellKeyOf(const openvdb::Coord& block, int cell_blocks) {
    const int cx = floorDiv(block.x(), cell_blocks), cy = floorDiv(block.y(), cell_blocks),
              cz = floorDiv(block.z(), cell_blocks);
    CellKey key;
    key.colour = static_cast<std::uint32_t>((cx & 1) * 4 + (cy & 1) * 2 + (cz & 1));
    key.cell = (static_cast<std::uint64_t>(cx & 0xFFFFF) << 40) |
               (static_cast<std::uint64_t>(cy & 0xFFFFF) << 20) | static_cast<std::uint64_t>(cz & 0xFFFFF);
    return key;
}

}  // namespace vdbmap::detail
