// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

/// Pairs of faces (by idx) that share a mesh edge, each pair once with first < second,
/// sorted. The smoothness graph of the texture and semantic MRFs.
std::vector<std::array<std::uint32_t, 2>> faceAdjacency(const TriMesh& mesh);

}  // namespace vdbmap
