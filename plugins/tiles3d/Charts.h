// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "TileMesh.h"

namespace vdbmap::tiles3d {

/// A texture chart: connected faces (across edges shared by exactly two faces) whose normals
/// share their dominant axis and its sign, laid flat by dropping that axis. Such a patch is a
/// height field over the plane of the other two axes, so its projection does not fold; a
/// chart whose projection still overlaps itself (a spiral) is split by the caller.
struct Chart {
    int axis = 2;                      ///< the dropped axis: 0 x, 1 y, 2 z
    std::vector<std::uint32_t> faces;  ///< in the order they joined (breadth first)
    double area_m2 = 0;                ///< the faces' area in W
    double projected_m2 = 0;           ///< their area on the chart's plane
    Eigen::Vector2d min_m{0, 0}, max_m{0, 0};  ///< the projected box (plane coordinates, metres)
    // The layout (bakeAtlas): metres per texel on the plane, the rectangle in texels with
    // its margins, and its place on the page.
    double plane_texel_m = 0;
    int w = 1, h = 1, x = 0, y = 0;
};

/// The plane coordinates of `p` (a point of W or relative to any origin) once `axis` is dropped.
inline Eigen::Vector2d projectToChart(const Eigen::Vector3d& p, int axis) {
    return axis == 0 ? Eigen::Vector2d(p.y(), p.z()) : axis == 1 ? Eigen::Vector2d(p.x(), p.z())
                                                                 : Eigen::Vector2d(p.x(), p.y());
}

/// The charts of a mesh, grown breadth first from the lowest unassigned face; a face joins
/// only while the chart's projected box stays within `max_side_m` on each side. Faces without
/// area get charts of their own. Deterministic (depends on the faces' order only).
std::vector<Chart> buildCharts(const TileMesh& mesh, double max_side_m);

/// A chart that overlaps itself, split: its faces not marked in `alone` (indices into
/// chart.faces) as one chart (first, if any), then one chart per marked face (same axis).
std::vector<Chart> splitChart(const TileMesh& mesh, const Chart& chart, const std::vector<std::uint32_t>& alone);

/// The point of 2D triangle `t` nearest to `q`: its barycentric weights, squared distance,
/// and whether q is strictly inside (a degenerate triangle has no inside).
struct Nearest2 {
    double distance2 = 0;
    Eigen::Vector3d weights{1, 0, 0};
    bool strictly_inside = false;
};
Nearest2 nearestOnTriangle2(const Eigen::Vector2d& q, const std::array<Eigen::Vector2d, 3>& t);

/// Which of a chart's faces each texel of its w x h rectangle shows: the nearest face whose
/// distance to the texel's centre is at most `reach_px` texels (ties: the earlier face), or
/// -1. `corners_px` are the faces' corners in the rectangle's texel coordinates (texel (c, r)
/// has its centre at (c + 0.5, r + 0.5)). Returns the faces (indices into corners_px, in
/// increasing order) of every pair whose insides both hold a texel centre: empty unless the
/// projection overlaps itself.
/// `inside` (if given) gets 1 for the texels whose centre lies in (or on) their face.
std::vector<std::uint32_t> rasterizeChart(const std::vector<std::array<Eigen::Vector2d, 3>>& corners_px, int w,
                                          int h, double reach_px, std::vector<std::int32_t>& owner,
                                          std::vector<std::uint8_t>* inside = nullptr);

}  // namespace vdbmap::tiles3d
