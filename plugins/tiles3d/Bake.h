// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include "MeshDistance.h"
#include "TileMesh.h"

namespace vdbmap::tiles3d {

/// What bakeAtlas did.
struct BakeFigures {
    double texel_m = 0;          ///< the texel size used (metres per texel)
    std::size_t texels = 0;      ///< texels baked (the page's packed rectangles)
    std::size_t charts = 0;      ///< charts on the page
    /// The largest distance from a texel's point on the target to the sources' surface (a
    /// measured distance: a lower bound of the target's distance to the sources).
    double max_texel_distance_m = 0;
    int page_width = 0, page_height = 0;
};

/// Metres per texel of a mesh's atlas: sqrt(area of its textured faces in W / their area on
/// the pages in pixels); 0 when no face is textured.
double texelSizeM(const TileMesh& mesh);

/// Gives `target` (its corners set, nothing else needed) a fresh atlas baked from `sources`,
/// and each face a class and confidence from them:
/// - the faces are cut into charts (buildCharts: connected faces whose normals share a
///   dominant axis, laid flat on that axis' plane, at most 256 texels on a side), each chart a
///   rectangle on one page with `gutter_px` texels of margin on each side, sizes rounded up to
///   even (JPEG's 2 x 2 chroma blocks never straddle two rectangles); a chart's plane texel is
///   `texel_m` x sqrt(its projected area / its area), so that its texels cover its surface at
///   `texel_m` metres per texel on average; `texel_m` grows until the packed page fits
///   `max_page_px` on a side;
/// - every texel of a chart within its margin plus one texel of a face shows the nearest
///   face (its point is clamped to the face, so margins repeat the faces' border colours and
///   bilinear sampling does not bleed); its colour is that of the nearest point of the
///   sources' surface: that point's texture coordinates on its face, sampled bilinearly in the
///   source's page (untextured source faces give the untextured material's grey);
/// - a face's class is the most frequent class of the source faces nearest to its texels
///   inside it (the nearest to its centroid when no texel centre falls inside), its
///   confidence their mean confidence for that class.
/// Without any textured source face the target gets no atlas (every face kNoPage).
/// Deterministic (parallel over charts, each writing its own rectangle and faces).
/// `sources_grid`, if given, holds the sources' faces in W in order (source by source, face by
/// face), as the caller may have built it already; else bakeAtlas builds it.
void bakeAtlas(TileMesh& target, const std::vector<const TileMesh*>& sources, double texel_m,
               int max_page_px, int gutter_px = 2, BakeFigures* figures = nullptr,
               const TriangleGrid* sources_grid = nullptr);

}  // namespace vdbmap::tiles3d
