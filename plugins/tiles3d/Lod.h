// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include "TileMesh.h"

namespace vdbmap::tiles3d {

struct ParentOptions {
    int level = 1;               ///< 1 = parent of the leaves
    double voxel_size_m = 0.1;   ///< the map's voxel size
    int max_atlas_px = 8192;     ///< the parent's atlas page side at most
};

/// What buildParent did.
struct ParentFigures {
    std::size_t merged_faces = 0, faces = 0;
    double simplify_error_m = 0;  ///< meshoptimizer's own error estimate (absolute)
    double texture_scale = 0;     ///< parent texels per child texel along an axis (0.5 or less)
};

/// A parent of the quadtree: the children's faces merged, welded (same position, texture
/// coordinate and page: texture borders stay seams; a face takes the class and confidence of
/// its first corner's first face) and simplified with
/// meshopt_simplify (LockBorder: the outline stays, so neighbouring parents meet without
/// cracks) to a quarter of the faces, at most voxel_size_m * 2^level of error; the children's
/// atlas pages halved (INTER_AREA) and packed into one page (smaller again if it would
/// exceed max_atlas_px). Every corner of the result is a corner of a child.
TileMesh buildParent(const std::vector<const TileMesh*>& children, const ParentOptions& options,
                     ParentFigures* figures = nullptr);

/// The faces as triangles in W.
std::vector<std::array<Eigen::Vector3d, 3>> trianglesW(const TileMesh& mesh);

}  // namespace vdbmap::tiles3d
