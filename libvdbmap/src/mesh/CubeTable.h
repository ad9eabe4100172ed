// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace vdbmap::detail {

/// Marching-cubes case table, generated (not copied) from the cube's topology.
/// Corner c in [0, 8) sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1). Edge e in [0, 12)
/// is axis e / 4 from corner kEdgeCorner[e] (whose bit `axis` is 0).
/// Case mask: bit c set when corner c is inside (sdf < 0). Triangles are lists of edges,
/// wound so that their normal points towards positive sdf (outside / in front).
struct CubeTable {
    std::array<std::uint8_t, 12> edge_corner{};  ///< lower corner of each edge
    std::array<std::uint8_t, 12> edge_axis{};
    /// Per case: triangles, 3 edges each.
    std::array<std::vector<std::array<std::uint8_t, 3>>, 256> triangles;
};

/// The table (built once, thread-safe static initialisation).
const CubeTable& cubeTable();

}  // namespace vdbmap::detail
