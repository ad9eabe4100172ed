// SPDX-License-Identifier: Apache-2.0
#include "MeshDistance.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vdbmap::tiles3d {

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Triangle& t) {
    const Eigen::Vector3d& a = t[0];
    const Eigen::Vector3d& b = t[1];
    const Eigen::Vector3d& c = t[2];
    const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Eigen::Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return a + v * ab;
    }
    const Eigen::Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return a + w * ac;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + w * (c - b);
    }
    const double denom = 1.0 / (va + vb + vc);
    if (!std::isfinite(denom)) {  // degenerate triangle: its edges
        Eigen::Vector3d best = a;
        for (const Eigen::Vector3d& q : {b, c}) {
            if ((p - q).squaredNorm() < (p - best).squaredNorm()) best = q;
        }
        for (const auto& [u, w] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            const Eigen::Vector3d e = w - u;
            const double l2 = e.squaredNorm();
            if (l2 <= 0) continue;
            const Eigen::Vector3d q = u + std::clamp((p - u).dot(e) / l2, 0.0, 1.0) * e;
            if ((p - q).squaredNorm() < (p - best).squaredNorm()) best = q;
        }
        return best;
    }
    const double v = vb * denom, w = vc * denom;
    return a + ab * v + ac * w;
}

double pointTriangleDistance(const Eigen::Vector3d& p, const Triangle& t) {
    return (p - closestPointOnTriangle(p, t)).norm();
}

Eigen::Vector3d barycentric(const Eigen::Vector3d& q, const Triangle& t) {
    const Eigen::Vector3d e0 = t[1] - t[0], e1 = t[2] - t[0], r = q - t[0];
    const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
    const double d20 = r.dot(e0), d21 = r.dot(e1);
    const double den = d00 * d11 - d01 * d01;
    if (!(std::abs(den) > 1e-30 * std::max(1.0, d00 * d11))) {
        int best = 0;
        for (int k = 1; k < 3; ++k) {
            if ((q - t[static_cast<std::size_t>(k)]).squaredNorm() < (q - t[static_cast<std::size_t>(best)]).squaredNorm()) best = k;
        }
        Eigen::Vector3d w = Eigen::Vector3d::Zero();
        w[best] = 1.0;
        return w;
    }
    const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    return {1.0 - v - w, v, w};
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
    lo_.resize(triangles_.size());
    hi_.resize(triangles_.size());
    for (std::size_t i = 0; i < triangles_.size(); ++i) {
        const Triangle& t = triangles_[i];
        lo_[i] = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
        hi_[i] = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
    }
    // About one triangle edge per cell, but at most ~32 M cells (128 MB of cell starts: a
    // 128 m x 128 m x 20 m parent of the 1.6 km drive gets 0.225 m cells, ~10 triangles each;
    // with 4 M cells it got 0.51 m, ~50 triangles to test per query).
    const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-6);
    cell_ = std::max(mean_edge, 1e-3);
    while ((extent / cell_).array().ceil().prod() > 32e6) cell_ *= 1.5;
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

double TriangleGrid::cellExit(const Eigen::Vector3d& q, const Eigen::Vector3i& c) const {
    // q in cell units; 0 when q lies outside cell c (a point beyond the grid's edge).
    const Eigen::Vector3d f = q - c.cast<double>();
    if ((f.array() < 0.0).any() || (f.array() > 1.0).any()) return 0.0;
    return f.cwiseMin(Eigen::Vector3d::Ones() - f).minCoeff() * cell_;
}

double TriangleGrid::distance(const Eigen::Vector3d& p) const {
    Eigen::Vector3d q;
    return nearest(p, q) < 0 ? std::numeric_limits<double>::infinity() : (p - q).norm();
}

int TriangleGrid::nearest(const Eigen::Vector3d& p, Eigen::Vector3d& nearest, int hint) const {
    if (triangles_.empty()) return -1;
    int best = -1;
    double best2 = std::numeric_limits<double>::infinity();
    auto consider = [&](std::uint32_t t) {
        const double box = (lo_[t] - p).cwiseMax(p - hi_[t]).cwiseMax(0.0).squaredNorm();
        if (box > best2) return;
        const Eigen::Vector3d q = closestPointOnTriangle(p, triangles_[t]);
        const double d2 = (p - q).squaredNorm();
        if (d2 < best2 || (d2 == best2 && static_cast<int>(t) < best)) {
            best2 = d2;
            best = static_cast<int>(t);
            nearest = q;
        }
    };
    if (hint >= 0 && static_cast<std::size_t>(hint) < triangles_.size()) consider(static_cast<std::uint32_t>(hint));
    const Eigen::Vector3d g = (p - origin_) / cell_;
    const Eigen::Vector3i c = g.array().floor().cast<int>().max(0).min(dims_.array() - 1).matrix();
    const double exit_m = cellExit(g, c);
    const int max_ring = dims_.maxCoeff();
    for (int r = 0; r <= max_ring; ++r) {
        // Every point of a cell in ring r is at least (r - 1) cells plus the way out of cell c
        // from p: stop once that exceeds the best distance (a tie there cannot be nearer).
        if (r >= 1 && (r - 1) * cell_ + exit_m > std::sqrt(best2)) break;
        for (int z = c.z() - r; z <= c.z() + r; ++z) {
            if (z < 0 || z >= dims_.z()) continue;
            for (int y = c.y() - r; y <= c.y() + r; ++y) {
                if (y < 0 || y >= dims_.y()) continue;
                for (int x = c.x() - r; x <= c.x() + r; ++x) {
                    if (x < 0 || x >= dims_.x()) continue;
                    if (std::max({std::abs(x - c.x()), std::abs(y - c.y()), std::abs(z - c.z())}) != r) continue;
                    const auto k = static_cast<std::size_t>(key(x, y, z));
                    for (std::uint32_t i = start_[k]; i < start_[k + 1]; ++i) consider(items_[i]);
                }
            }
        }
    }
    return best;
}

namespace {

std::array<std::uint64_t, 3> pointBits(const Eigen::Vector3d& p) {
    std::array<std::uint64_t, 3> k;
    for (int i = 0; i < 3; ++i) {
        const double v = p[i] == 0.0 ? 0.0 : p[i];  // -0 and +0 are one point
        std::memcpy(&k[static_cast<std::size_t>(i)], &v, sizeof v);
    }
    return k;
}

struct PointBitsHash {
    std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (const std::uint64_t v : k) h = (h ^ v ^ (v >> 32)) * 1099511628211ull;
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

}  // namespace

double hausdorffBound(const std::vector<Triangle>& a, const TriangleGrid& b, double tolerance_m,
                      std::size_t* samples, double known_m) {
    // Breadth first, in rounds: the triangles of a round are tested against the largest
    // distance found before it (a lower bound of the maximum); those whose bound exceeds it by
    // more than the tolerance are split in four, their new midpoints evaluated in parallel.
    // Every decision depends only on the round's inputs: the result does not depend on the
    // threads.
    struct Item {
        Triangle t;
        std::array<double, 3> d;
        int depth;
    };
    // The covering radius: every point of the triangle is within it of a corner. Acute: the
    // circumradius (the circumcentre is the farthest point from the corners); right or obtuse:
    // half the longest edge bounds it (the corners' disks of that radius cover the triangle).
    // Both are at most longest edge / sqrt 3.
    auto radius = [](const Triangle& t) {
        const double a2 = (t[1] - t[0]).squaredNorm(), b2 = (t[2] - t[1]).squaredNorm(), c2 = (t[0] - t[2]).squaredNorm();
        const double l2 = std::max({a2, b2, c2});
        const double twice_area = (t[1] - t[0]).cross(t[2] - t[0]).norm();
        if (2 * l2 >= a2 + b2 + c2 || !(twice_area > 0)) return 0.5 * std::sqrt(l2);
        return std::min(std::sqrt(a2 * b2 * c2) / (2 * twice_area), std::sqrt(l2 / 3.0));
    };
    // The corners first, each distinct point once (a mesh's corners are shared by ~6 faces).
    std::unordered_map<std::array<std::uint64_t, 3>, std::uint32_t, PointBitsHash> index_of;
    index_of.reserve(a.size() * 2);
    std::vector<Eigen::Vector3d> points;
    std::vector<std::array<std::uint32_t, 3>> corner_index(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        for (std::size_t k = 0; k < 3; ++k) {
            const auto it = index_of.emplace(pointBits(a[i][k]), static_cast<std::uint32_t>(points.size()));
            if (it.second) points.push_back(a[i][k]);
            corner_index[i][k] = it.first->second;
        }
    }
    index_of.clear();
    std::vector<double> point_d(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) point_d[i] = b.distance(points[i]);
    });
    std::vector<Item> active(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        const auto& c = corner_index[i];
        active[i] = {a[i], {point_d[c[0]], point_d[c[1]], point_d[c[2]]}, 0};
    }
    std::size_t queries = points.size();
    double lower = std::max(0.0, known_m), upper = 0.0;
    for (const Item& item : active) lower = std::max({lower, item.d[0], item.d[1], item.d[2]});
    std::vector<Item> split;
    while (!active.empty()) {
        split.clear();
        for (const Item& item : active) {
            const double bound = std::max({item.d[0], item.d[1], item.d[2]}) + radius(item.t);
            if (bound <= lower + tolerance_m || item.depth >= 20) {
                upper = std::max(upper, bound);
            } else {
                split.push_back(item);
            }
        }
        // The new midpoints, each distinct point once (neighbours split in the same round
        // share an edge's midpoint: 0.5 (a + b) is the same double either way).
        std::vector<std::array<std::uint32_t, 3>> mid_index(split.size());
        points.clear();
        for (std::size_t i = 0; i < split.size(); ++i) {
            const Triangle& t = split[i].t;
            for (std::size_t k = 0; k < 3; ++k) {
                const Eigen::Vector3d m = 0.5 * (t[k] + t[(k + 1) % 3]);
                const auto it = index_of.emplace(pointBits(m), static_cast<std::uint32_t>(points.size()));
                if (it.second) points.push_back(m);
                mid_index[i][k] = it.first->second;
            }
        }
        index_of.clear();
        point_d.resize(points.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) point_d[i] = b.distance(points[i]);
        });
        queries += points.size();
        std::vector<Item> next(4 * split.size());
        for (std::size_t i = 0; i < split.size(); ++i) {
            const Item& item = split[i];
            const Eigen::Vector3d& m01 = points[mid_index[i][0]];
            const Eigen::Vector3d& m12 = points[mid_index[i][1]];
            const Eigen::Vector3d& m20 = points[mid_index[i][2]];
            const double d01 = point_d[mid_index[i][0]], d12 = point_d[mid_index[i][1]], d20 = point_d[mid_index[i][2]];
            const int depth = item.depth + 1;
            next[4 * i] = {{item.t[0], m01, m20}, {item.d[0], d01, d20}, depth};
            next[4 * i + 1] = {{m01, item.t[1], m12}, {d01, item.d[1], d12}, depth};
            next[4 * i + 2] = {{m20, m12, item.t[2]}, {d20, d12, item.d[2]}, depth};
            next[4 * i + 3] = {{m01, m12, m20}, {d01, d12, d20}, depth};
        }
        for (const Item& item : next) lower = std::max({lower, item.d[0], item.d[1], item.d[2]});
        active.swap(next);
    }
    if (samples) *samples = queries;
    return std::max(upper, lower);
}

}  // namespace vdbmap::tiles3d
