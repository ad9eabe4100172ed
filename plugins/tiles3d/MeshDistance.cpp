// SPDX-License-Identifier: Apache-2.0
#include "MeshDistance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vdbmap::tiles3d {

double pointTriangleDistance(const Eigen::Vector3d& p, const Triangle& t) {
    const Eigen::Vector3d& a = t[0];
    const Eigen::Vector3d& b = t[1];
    const Eigen::Vector3d& c = t[2];
    const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return (p - a).norm();
    const Eigen::Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return (p - b).norm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return (p - (a + v * ab)).norm();
    }
    const Eigen::Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return (p - c).norm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return (p - (a + w * ac)).norm();
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + w * (c - b))).norm();
    }
    const double denom = 1.0 / (va + vb + vc);
    if (!std::isfinite(denom)) {  // degenerate triangle: its edges
        double best = std::min({(p - a).norm(), (p - b).norm(), (p - c).norm()});
        for (const auto& [u, w] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            const Eigen::Vector3d e = w - u;
            const double l2 = e.squaredNorm();
            if (l2 > 0) best = std::min(best, (p - (u + std::clamp((p - u).dot(e) / l2, 0.0, 1.0) * e)).norm());
        }
        return best;
    }
    const double v = vb * denom, w = vc * denom;
    return (p - (a + ab * v + ac * w)).norm();
}

TriangleGrid::TriangleGrid(std::vector<Triangle> triangles) : triangles_(std::move(triangles)) {
    if (triangles_.empty()) return;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    double edge_sum = 0;
    for (const Triangle& t : triangles_) {
        for (int k = 0; k < 3; ++k) {
            lo = lo.cwiseMin(t[static_cast<std::size_t>(k)]);
            hi = hi.cwiseMax(t[static_cast<std::size_t>(k)]);
        }
        edge_sum += (t[1] - t[0]).norm();
    }
    const double mean_edge = edge_sum / static_cast<double>(triangles_.size());
    // About two triangles' edge per cell, but at most ~4 M cells.
    const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-6);
    cell_ = std::max(2.0 * mean_edge, 1e-3);
    while ((extent / cell_).array().ceil().prod() > 4e6) cell_ *= 1.5;
    origin_ = lo;
    dims_ = ((extent / cell_).array().floor().cast<int>() + 1).matrix();
    const std::size_t cells = static_cast<std::size_t>(dims_.x()) * dims_.y() * dims_.z();
    std::vector<std::uint32_t> counts(cells + 1, 0);
    auto range = [&](const Triangle& t, Eigen::Vector3i& a, Eigen::Vector3i& b) {
        Eigen::Vector3d tl = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
        Eigen::Vector3d th = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
        a = ((tl - origin_) / cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1).matrix();
        b = ((th - origin_) / cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1).matrix();
    };
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            for (std::size_t i = 1; i <= cells; ++i) counts[i] += counts[i - 1];
            start_ = counts;
            items_.resize(counts[cells]);
        }
        for (std::size_t i = 0; i < triangles_.size(); ++i) {
            Eigen::Vector3i a, b;
            range(triangles_[i], a, b);
            for (int z = a.z(); z <= b.z(); ++z)
                for (int y = a.y(); y <= b.y(); ++y)
                    for (int x = a.x(); x <= b.x(); ++x) {
                        const auto k = static_cast<std::size_t>(key(x, y, z));
                        if (pass == 0) ++counts[k + 1];
                        else items_[counts[k]++] = static_cast<std::uint32_t>(i);
                    }
        }
    }
}

std::int64_t TriangleGrid::key(int x, int y, int z) const {
    return (static_cast<std::int64_t>(z) * dims_.y() + y) * dims_.x() + x;
}

double TriangleGrid::distance(const Eigen::Vector3d& p) const {
    double best = std::numeric_limits<double>::infinity();
    if (triangles_.empty()) return best;
    const Eigen::Vector3d q = (p - origin_) / cell_;
    const Eigen::Vector3i c = q.array().floor().cast<int>().max(0).min(dims_.array() - 1).matrix();
    const int max_ring = dims_.maxCoeff();
    for (int r = 0; r <= max_ring; ++r) {
        // Every point of a cell in ring r is at least (r - 1) cells from p (p in cell c, or
        // outside the grid beyond it): stop once that exceeds the best distance.
        if (r >= 1 && (r - 1) * cell_ > best) break;
        for (int z = c.z() - r; z <= c.z() + r; ++z) {
            if (z < 0 || z >= dims_.z()) continue;
            for (int y = c.y() - r; y <= c.y() + r; ++y) {
                if (y < 0 || y >= dims_.y()) continue;
                for (int x = c.x() - r; x <= c.x() + r; ++x) {
                    if (x < 0 || x >= dims_.x()) continue;
                    if (std::max({std::abs(x - c.x()), std::abs(y - c.y()), std::abs(z - c.z())}) != r) continue;
                    const auto k = static_cast<std::size_t>(key(x, y, z));
                    for (std::uint32_t i = start_[k]; i < start_[k + 1]; ++i) {
                        best = std::min(best, pointTriangleDistance(p, triangles_[items_[i]]));
                    }
                }
            }
        }
    }
    return best;
}

double hausdorffBound(const std::vector<Triangle>& a, const TriangleGrid& b, double tolerance_m,
                      std::size_t* samples) {
    // Phase 1: the largest corner distance, a lower bound of the maximum (parallel; max is
    // order-free). Phase 2: each triangle on its own against that fixed lower bound, so that the
    // result does not depend on the order or the threads.
    auto radius = [](const Triangle& t) {
        return std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()}) /
               std::sqrt(3.0);
    };
    std::vector<std::array<double, 3>> corner(a.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, a.size(), 256), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            for (std::size_t k = 0; k < 3; ++k) corner[i][k] = b.distance(a[i][k]);
        }
    });
    double lower = 0.0;
    for (const auto& d : corner) lower = std::max({lower, d[0], d[1], d[2]});
    const double threshold = lower + tolerance_m;
    std::vector<double> upper(a.size(), 0.0);
    std::vector<std::size_t> queries(a.size(), 3);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, a.size(), 64), [&](const auto& r) {
        struct Item {
            Triangle t;
            std::array<double, 3> d;
            int depth;
        };
        std::vector<Item> stack;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            stack.clear();
            stack.push_back({a[i], corner[i], 0});
            double up = 0.0;
            while (!stack.empty()) {
                const Item item = stack.back();
                stack.pop_back();
                const double dmax = std::max({item.d[0], item.d[1], item.d[2]});
                const double bound = dmax + radius(item.t);
                if (bound <= threshold || item.depth >= 20) {
                    up = std::max(up, bound);
                    continue;
                }
                const Eigen::Vector3d m01 = 0.5 * (item.t[0] + item.t[1]);
                const Eigen::Vector3d m12 = 0.5 * (item.t[1] + item.t[2]);
                const Eigen::Vector3d m20 = 0.5 * (item.t[2] + item.t[0]);
                const double d01 = b.distance(m01), d12 = b.distance(m12), d20 = b.distance(m20);
                queries[i] += 3;
                const int depth = item.depth + 1;
                stack.push_back({{item.t[0], m01, m20}, {item.d[0], d01, d20}, depth});
                stack.push_back({{m01, item.t[1], m12}, {d01, item.d[1], d12}, depth});
                stack.push_back({{m20, m12, item.t[2]}, {d20, d12, item.d[2]}, depth});
                stack.push_back({{m01, m12, m20}, {d01, d12, d20}, depth});
            }
            upper[i] = up;
        }
    });
    double result = lower;
    std::size_t total = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        result = std::max(result, upper[i]);
        total += queries[i];
    }
    if (samples) *samples = total;
    return result;
}

}  // namespace vdbmap::tiles3d
