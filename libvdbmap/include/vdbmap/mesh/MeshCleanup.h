// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vdbmap {

/// Removes the faces of connected components (faces sharing a vertex) with fewer than
/// `min_faces` faces, keeping the order of the remaining faces. Vertices are not touched
/// (unreferenced vertices remain). Returns the number of components removed; `faces_removed`
/// receives the number of faces removed. min_faces <= 1 is a no-op.
std::size_t removeSmallComponents(std::vector<std::array<std::uint32_t, 3>>& faces,
                                  std::size_t num_vertices, int min_faces,
                                  std::size_t* faces_removed = nullptr);

}  // namespace vdbmap
