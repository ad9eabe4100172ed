// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include "MeshDistance.h"
#include "TileMesh.h"

namespace vdbmap::tiles3d {

struct ParentOptions {
    int level = 1;               ///< 1 = parent of the leaves
    double voxel_size_m = 0.1;   ///< the map's voxel size
    int max_atlas_px = 8192;     ///< the parent's atlas page side at most
    int gutter_px = 2;           ///< texels of margin around each face on the parent's page
};

/// What buildParent did.
struct ParentFigures {
    std::size_t merged_faces = 0, faces = 0;
    double simplify_error_m = 0;  ///< meshoptimizer's own error estimate (absolute)
    double child_texel_m = 0;     ///< the children's texel size (metres per texel)
    double texel_m = 0;           ///< the parent's (2 x the children's, more if the page was full)
    std::size_t texels = 0;       ///< texels baked
    std::size_t charts = 0;       ///< charts on the parent's page
    double weld_s = 0, simplify_s = 0, bake_s = 0;  ///< wall time of each step
    double max_texel_distance_m = 0;  ///< BakeFigures::max_texel_distance_m
};

/// A parent of the quadtree: the children's faces merged, welded by position only (texture
/// seams and class borders are no borders), simplified with meshopt_simplify to a quarter of
/// the faces, at most voxel_size_m * 2^level of error (no LockBorder: border vertices still
/// collapse only along the border); then a fresh atlas at twice the children's texel size,
/// baked from the children's surface and pages, and each face's class and confidence from the
/// children's faces nearest to it (bakeAtlas). Every corner of the result is a corner of a
/// child.
/// `children_grid`, if given, holds the children's faces in W in order (bakeAtlas).
TileMesh buildParent(const std::vector<const TileMesh*>& children, const ParentOptions& options,
                     ParentFigures* figures = nullptr, const TriangleGrid* children_grid = nullptr);

/// The faces as triangles in W.
std::vector<std::array<Eigen::Vector3d, 3>> trianglesW(const TileMesh& mesh);

}  // namespace vdbmap::tiles3d
