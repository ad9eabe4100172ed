// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap::tiles3d {

using Triangle = std::array<Eigen::Vector3d, 3>;

/// Nearest-triangle queries on a fixed set of triangles (a uniform grid of their boxes).
class TriangleGrid {
public:
    explicit TriangleGrid(std::vector<Triangle> triangles);
    /// Distance from `p` to the nearest triangle (exact point-triangle distance); +inf when
    /// there are no triangles.
    double distance(const Eigen::Vector3d& p) const;
    std::size_t size() const { return triangles_.size(); }
    const Triangle& triangle(std::size_t i) const { return triangles_[i]; }
    /// The triangle nearest to `p` (ties: the smaller index) and the nearest point on it, by a
    /// search in rings of grid cells around p; -1 when there are no triangles. `hint` (a
    /// triangle index, or -1) is tried first to bound the search; the answer does not depend
    /// on it. Thread-safe.
    int nearest(const Eigen::Vector3d& p, Eigen::Vector3d& nearest, int hint = -1) const;

private:
    std::int64_t key(int x, int y, int z) const;
    /// The distance (metres) from a point, `q` in cell units, to the outside of its cell `c`.
    double cellExit(const Eigen::Vector3d& q, const Eigen::Vector3i& c) const;
    std::vector<Triangle> triangles_;
    std::vector<Eigen::Vector3d> lo_, hi_;  ///< each triangle's box
    Eigen::Vector3d origin_;
    double cell_ = 1.0;
    Eigen::Vector3i dims_;
    std::vector<std::uint32_t> start_, items_;  // CSR: cell -> triangles
};

/// Distance from `p` to triangle `t` (Ericson, Real-Time Collision Detection 5.1.5).
double pointTriangleDistance(const Eigen::Vector3d& p, const Triangle& t);
/// The point of triangle `t` nearest to `p` (the same construction).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Triangle& t);
/// Barycentric coordinates of `q` (a point of the triangle's plane) in `t`; a degenerate
/// triangle gives the weights of its nearest corner.
Eigen::Vector3d barycentric(const Eigen::Vector3d& q, const Triangle& t);

/// An upper bound on the one-sided Hausdorff distance max_{a in A} min_{b in B} |a - b| from
/// the surface of `a` to the surface of `b`, within `tolerance_m` of the true value:
/// distance-to-B is 1-Lipschitz, so over a triangle it is at most its largest corner value plus
/// the triangle's covering radius (acute: its circumradius; else half its longest edge; both
/// <= longest edge / sqrt 3); triangles whose bound exceeds the
/// largest distance found so far by more than the tolerance are split in four (branch and
/// bound, breadth first in rounds). Parallel (TBB) and independent of the thread count. `samples` (if
/// given) receives the number of distance queries.
/// `known_m`: a distance from a point of `a` to `b` the caller has measured already (a lower
/// bound of the maximum: triangles within it plus the tolerance need no split); 0 = none.
double hausdorffBound(const std::vector<Triangle>& a, const TriangleGrid& b, double tolerance_m,
                      std::size_t* samples = nullptr, double known_m = 0.0);

}  // namespace vdbmap::tiles3d
