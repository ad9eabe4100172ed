// SPDX-License-Identifier: Apache-2.0
// The volume the simulated traffic swept, and the ghost area of a mesh inside it.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "vdbmap/eval/TrafficMetrics.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

SweptVolume::SweptVolume(const MoversFile& movers, double inflate_m) {
    const Vec3f pad = Vec3f::Constant(static_cast<float>(inflate_m));
    bool have_up = false;
    for (const Mover& m : movers.movers) {
        const Vec3f c = m.boxCentre_O(), h = m.boxHalf_m();
        const Eigen::AlignedBox3f box_O(c - h - pad, c + h + pad);
        for (const Isometry3d& T : m.T_W_O) {
            Box b;
            const Eigen::Isometry3f T_W_O = T.cast<float>();
            b.T_O_W = T_W_O.inverse();
            b.box_O = box_O;
            for (int k = 0; k < 8; ++k) {
                b.bounds_W.extend(T_W_O *
                                  box_O.corner(static_cast<Eigen::AlignedBox3f::CornerType>(k)));
            }
            bounds_W_.extend(b.bounds_W);
            boxes_.push_back(b);
            if (!have_up) {
                up_W_ = T_W_O.linear().col(2).normalized();
                have_up = true;
            }
        }
    }
}

bool SweptVolume::contains(const Vec3f& p_W) const {
    if (boxes_.empty() || !bounds_W_.contains(p_W)) return false;
    for (const Box& b : boxes_) {
        if (b.bounds_W.contains(p_W) && b.box_O.contains(b.T_O_W * p_W)) return true;
    }
    return false;
}

double SweptVolume::groundArea(double cell_m) const {
    if (boxes_.empty() || !(cell_m > 0)) return 0.0;
    // A ground basis (e1, e2) perpendicular to the up axis; each box projects to a rectangle.
    const Vec3f e1 = up_W_.unitOrthogonal();
    const Vec3f e2 = up_W_.cross(e1);
    using Vec2 = Eigen::Vector2d;
    std::vector<std::array<Vec2, 4>> quads;
    Vec2 lo(1e30, 1e30), hi(-1e30, -1e30);
    for (const Box& b : boxes_) {
        const Eigen::Isometry3f T_W_O = b.T_O_W.inverse();
        const Vec3f mn = b.box_O.min(), mx = b.box_O.max();
        const Vec3f corners_O[4] = {{mn.x(), mn.y(), mn.z()},
                                    {mx.x(), mn.y(), mn.z()},
                                    {mx.x(), mx.y(), mn.z()},
                                    {mn.x(), mx.y(), mn.z()}};
        std::array<Vec2, 4> q;
        for (int k = 0; k < 4; ++k) {
            const Vec3f p = T_W_O * corners_O[k];
            q[k] = Vec2(p.dot(e1), p.dot(e2));
            lo = lo.cwiseMin(q[k]);
            hi = hi.cwiseMax(q[k]);
        }
        quads.push_back(q);
    }
    const auto nx = static_cast<std::size_t>(std::ceil((hi.x() - lo.x()) / cell_m)) + 1;
    const auto ny = static_cast<std::size_t>(std::ceil((hi.y() - lo.y()) / cell_m)) + 1;
    std::vector<std::uint8_t> covered(nx * ny, 0);
    for (const auto& q : quads) {
        // Orientation of the quad (the projection may mirror it).
        const double sign =
            (q[1] - q[0]).x() * (q[2] - q[1]).y() - (q[1] - q[0]).y() * (q[2] - q[1]).x() >= 0
                ? 1.0
                : -1.0;
        Vec2 qlo = q[0], qhi = q[0];
        for (const auto& p : q) qlo = qlo.cwiseMin(p), qhi = qhi.cwiseMax(p);
        const auto i0 = static_cast<std::size_t>(std::floor((qlo.x() - lo.x()) / cell_m));
        const auto i1 = std::min(nx - 1, static_cast<std::size_t>((qhi.x() - lo.x()) / cell_m));
        const auto j0 = static_cast<std::size_t>(std::floor((qlo.y() - lo.y()) / cell_m));
        const auto j1 = std::min(ny - 1, static_cast<std::size_t>((qhi.y() - lo.y()) / cell_m));
        for (std::size_t j = j0; j <= j1; ++j) {
            for (std::size_t i = i0; i <= i1; ++i) {
                const Vec2 c(lo.x() + (i + 0.5) * cell_m, lo.y() + (j + 0.5) * cell_m);
                bool inside = true;
                for (int k = 0; k < 4 && inside; ++k) {
                    const Vec2 a = q[k], d = q[(k + 1) % 4] - q[k];
                    inside = sign * (d.x() * (c.y() - a.y()) - d.y() * (c.x() - a.x())) >= 0;
                }
                if (inside) covered[j * nx + i] = 1;
            }
        }
    }
    const auto n = static_cast<double>(std::count(covered.begin(), covered.end(), 1));
    return n * cell_m * cell_m;
}

std::vector<double> ghostAreaPerFace(const std::vector<Vec3f>& vertices,
                                     const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                     const Raycaster& static_gt, const SweptVolume& swept,
                                     double ghost_distance_m, double sample_spacing_m) {
    std::vector<double> area(triangles.size(), 0.0);
    if (swept.numBoxes() == 0 || triangles.empty()) return area;
    const double spacing = sample_spacing_m > 0 ? sample_spacing_m : 0.02;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, triangles.size()),
        [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t t = range.begin(); t != range.end(); ++t) {
                const Vec3f& a = vertices[triangles[t][0]];
                const Vec3f& b = vertices[triangles[t][1]];
                const Vec3f& c = vertices[triangles[t][2]];
                Eigen::AlignedBox3f tb(a);
                tb.extend(b).extend(c);
                if (!tb.intersects(swept.bounds())) continue;
                const double tri_area = 0.5 * static_cast<double>((b - a).cross(c - a).norm());
                const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
                const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
                // The n^2 sub-triangles of the regular subdivision: centroids at barycentric
                // ((i + 1/3) / n, (j + 1/3) / n) (upright) and ((i + 2/3) / n, (j + 2/3) / n)
                // (inverted), each of area tri_area / n^2.
                std::size_t ghost = 0;
                const Vec3f e1 = b - a, e2 = c - a;
                for (int i = 0; i < n; ++i) {
                    for (int j = 0; i + j < n; ++j) {
                        for (int inverted = 0; inverted < 2; ++inverted) {
                            if (inverted && i + j + 1 >= n) continue;
                            const float off = inverted ? 2.0f / 3.0f : 1.0f / 3.0f;
                            const Vec3f p = a + e1 * ((i + off) / n) + e2 * ((j + off) / n);
                            if (!swept.contains(p)) continue;
                            if (static_gt.closestPoint(p, static_cast<float>(ghost_distance_m))) {
                                continue;  // within the distance of the static world
                            }
                            ++ghost;
                        }
                    }
                }
                area[t] = tri_area * static_cast<double>(ghost) / (static_cast<double>(n) * n);
            }
        });
    return area;
}

double ghostArea(const std::vector<Vec3f>& vertices,
                 const std::vector<std::array<std::uint32_t, 3>>& triangles,
                 const Raycaster& static_gt, const SweptVolume& swept, double ghost_distance_m,
                 double sample_spacing_m) {
    double total = 0.0;
    for (double v : ghostAreaPerFace(vertices, triangles, static_gt, swept, ghost_distance_m,
                                     sample_spacing_m)) {
        total += v;
    }
    return total;
}

}  // namespace vdbmap
