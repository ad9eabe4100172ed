// SPDX-License-Identifier: Apache-2.0
// Note: this file is Apache-2.0, but it is compiled against CGAL's GPL-3.0-or-later
// Surface_mesh_simplification package; see README.md in this folder.
#pragma once

#include <cstddef>

#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap::cgal {

struct SimplifyOptions {
    double target_ratio = 0.25;  ///< stop when at most this fraction of the edges remain, (0, 1]
    double max_error_m = 0.02;   ///< no collapse may place a vertex further than this from the input
};

struct SimplifyResult {
    std::size_t faces_in = 0;
    std::size_t faces_out = 0;
    std::size_t faces_skipped = 0;  ///< non-manifold faces CGAL could not take (dropped)
    std::size_t collapsed_edges = 0;
};

/// Garland–Heckbert plane-quadric edge collapse with a bounded-distance placement. Replaces
/// `mesh` by the simplified mesh with fresh vertex normals. An empty mesh is a no-op. Throws
/// InvalidInput on options out of range.
SimplifyResult simplifyMesh(TriMesh& mesh, const SimplifyOptions& options);

}  // namespace vdbmap::cgal
