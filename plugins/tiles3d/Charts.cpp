// SPDX-License-Identifier: Apache-2.0
#include "Charts.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <unordered_map>

namespace vdbmap::tiles3d {
namespace {

struct FloatKeyHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (const std::uint32_t v : k) h = (h ^ v) * 1099511628211ull;
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

std::uint32_t bits(float v) {
    if (v == 0.0f) v = 0.0f;  // -0 and +0 are one position
    std::uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

/// -1 for a face without area, else 2 x dominant axis + (1 if the normal points down it).
int normalClass(const std::array<Eigen::Vector3f, 3>& c) {
    const Eigen::Vector3d n = (c[1] - c[0]).cast<double>().cross((c[2] - c[0]).cast<double>());
    if (!(n.squaredNorm() > 1e-24)) return -1;
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
        if (std::abs(n[a]) > std::abs(n[axis])) axis = a;
    }
    return 2 * axis + (n[axis] < 0 ? 1 : 0);
}

void addFace(Chart& chart, const TileMesh& mesh, std::uint32_t f) {
    const auto& c = mesh.corners[f];
    std::array<Eigen::Vector2d, 3> p;
    for (std::size_t k = 0; k < 3; ++k) p[k] = projectToChart(c[k].cast<double>(), chart.axis);
    if (chart.faces.empty()) {
        chart.min_m = chart.max_m = p[0];
    }
    for (const auto& q : p) {
        chart.min_m = chart.min_m.cwiseMin(q);
        chart.max_m = chart.max_m.cwiseMax(q);
    }
    chart.area_m2 += 0.5 * (c[1] - c[0]).cast<double>().cross((c[2] - c[0]).cast<double>()).norm();
    const Eigen::Vector2d a = p[1] - p[0], b = p[2] - p[0];
    chart.projected_m2 += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    chart.faces.push_back(f);
}

}  // namespace

std::vector<Chart> buildCharts(const TileMesh& mesh, double max_side_m) {
    const std::size_t n = mesh.faces();
    // Vertices by their exact position (the parents' corners are welded vertices).
    std::unordered_map<std::array<std::uint32_t, 3>, std::uint32_t, FloatKeyHash> id_of;
    id_of.reserve(n * 2);
    std::vector<std::array<std::uint32_t, 3>> fv(n);
    std::vector<int> cls(n);
    for (std::size_t f = 0; f < n; ++f) {
        for (std::size_t k = 0; k < 3; ++k) {
            const Eigen::Vector3f& p = mesh.corners[f][k];
            const auto it = id_of.emplace(std::array<std::uint32_t, 3>{bits(p.x()), bits(p.y()), bits(p.z())},
                                          static_cast<std::uint32_t>(id_of.size()));
            fv[f][k] = it.first->second;
        }
        cls[f] = normalClass(mesh.corners[f]);
    }
    id_of.clear();
    // Edges: the first two faces and how many faces share each.
    struct EdgeFaces {
        std::uint32_t a = 0, b = 0, count = 0;
    };
    std::unordered_map<std::uint64_t, EdgeFaces> edges;
    edges.reserve(n * 2);
    auto edgeKey = [&](std::size_t f, std::size_t k) {
        const std::uint64_t u = fv[f][k], v = fv[f][(k + 1) % 3];
        return std::min(u, v) << 32 | std::max(u, v);
    };
    for (std::size_t f = 0; f < n; ++f) {
        for (std::size_t k = 0; k < 3; ++k) {
            if (fv[f][k] == fv[f][(k + 1) % 3]) continue;
            EdgeFaces& e = edges[edgeKey(f, k)];
            if (e.count == 0) e.a = static_cast<std::uint32_t>(f);
            if (e.count == 1) e.b = static_cast<std::uint32_t>(f);
            ++e.count;
        }
    }

    std::vector<Chart> charts;
    std::vector<bool> assigned(n, false);
    std::deque<std::uint32_t> queue;
    for (std::size_t seed = 0; seed < n; ++seed) {
        if (assigned[seed]) continue;
        Chart chart;
        chart.axis = cls[seed] < 0 ? 2 : cls[seed] / 2;
        assigned[seed] = true;
        addFace(chart, mesh, static_cast<std::uint32_t>(seed));
        if (cls[seed] >= 0) queue.push_back(static_cast<std::uint32_t>(seed));
        while (!queue.empty()) {
            const std::uint32_t f = queue.front();
            queue.pop_front();
            for (std::size_t k = 0; k < 3; ++k) {
                if (fv[f][k] == fv[f][(k + 1) % 3]) continue;
                const EdgeFaces& e = edges.at(edgeKey(f, k));
                if (e.count != 2) continue;  // borders and non-manifold edges end a chart
                const std::uint32_t g = e.a == f ? e.b : e.a;
                if (assigned[g] || cls[g] != cls[f]) continue;
                Eigen::Vector2d lo = chart.min_m, hi = chart.max_m;
                for (const auto& c : mesh.corners[g]) {
                    const Eigen::Vector2d q = projectToChart(c.cast<double>(), chart.axis);
                    lo = lo.cwiseMin(q);
                    hi = hi.cwiseMax(q);
                }
                if ((hi - lo).maxCoeff() > max_side_m) continue;
                assigned[g] = true;
                addFace(chart, mesh, g);
                queue.push_back(g);
            }
        }
        charts.push_back(std::move(chart));
    }
    return charts;
}

std::vector<Chart> splitChart(const TileMesh& mesh, const Chart& chart, const std::vector<std::uint32_t>& alone) {
    std::vector<bool> marked(chart.faces.size(), false);
    for (const std::uint32_t j : alone) marked[j] = true;
    std::vector<Chart> out(1);
    out.front().axis = chart.axis;
    for (std::size_t j = 0; j < chart.faces.size(); ++j) {
        if (!marked[j]) addFace(out.front(), mesh, chart.faces[j]);
    }
    if (out.front().faces.empty()) out.clear();
    for (std::size_t j = 0; j < chart.faces.size(); ++j) {
        if (!marked[j]) continue;
        Chart c;
        c.axis = chart.axis;
        addFace(c, mesh, chart.faces[j]);
        out.push_back(std::move(c));
    }
    return out;
}

Nearest2 nearestOnTriangle2(const Eigen::Vector2d& q, const std::array<Eigen::Vector2d, 3>& t) {
    const Eigen::Vector2d e1 = t[1] - t[0], e2 = t[2] - t[0], r = q - t[0];
    const double det = e1.x() * e2.y() - e1.y() * e2.x();
    if (std::abs(det) > 1e-12) {
        const double b1 = (r.x() * e2.y() - r.y() * e2.x()) / det;
        const double b2 = (e1.x() * r.y() - e1.y() * r.x()) / det;
        const double b0 = 1.0 - b1 - b2;
        if (b0 >= 0 && b1 >= 0 && b2 >= 0) {
            Nearest2 out;
            out.weights = Eigen::Vector3d(b0, b1, b2);
            out.strictly_inside = b0 > 1e-9 && b1 > 1e-9 && b2 > 1e-9;
            return out;
        }
    }
    Nearest2 best;
    best.distance2 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d& a = t[static_cast<std::size_t>(k)];
        const Eigen::Vector2d ab = t[static_cast<std::size_t>((k + 1) % 3)] - a;
        const double len2 = ab.squaredNorm();
        const double s = len2 > 0 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
        const double d2 = (q - (a + s * ab)).squaredNorm();
        if (d2 < best.distance2) {
            best.distance2 = d2;
            best.weights.setZero();
            best.weights[k] = 1.0 - s;
            best.weights[(k + 1) % 3] += s;
        }
    }
    return best;
}

std::vector<std::uint32_t> rasterizeChart(const std::vector<std::array<Eigen::Vector2d, 3>>& corners_px, int w,
                                          int h, double reach_px, std::vector<std::int32_t>& owner,
                                          std::vector<std::uint8_t>* inside_out) {
    owner.assign(std::size_t(w) * std::size_t(h), -1);
    std::vector<double> best(owner.size(), std::numeric_limits<double>::infinity());
    std::vector<std::int32_t> inside(owner.size(), -1);  // the first face strictly inside
    std::vector<bool> overlapping(corners_px.size(), false);
    const double reach2 = reach_px * reach_px;
    auto texelRange = [&](const std::array<Eigen::Vector2d, 3>& t, double margin, int& c0, int& c1, int& r0, int& r1) {
        const Eigen::Vector2d lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]).array() - margin;
        const Eigen::Vector2d hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]).array() + margin;
        c0 = std::max(0, static_cast<int>(std::floor(lo.x() - 0.5)));
        c1 = std::min(w - 1, static_cast<int>(std::ceil(hi.x() - 0.5)));
        r0 = std::max(0, static_cast<int>(std::floor(lo.y() - 0.5)));
        r1 = std::min(h - 1, static_cast<int>(std::ceil(hi.y() - 0.5)));
    };
    // First the texel centres inside a face (the earlier face where two share an edge), then
    // the nearest face of every other texel within reach: the same owners as one pass that
    // keeps the strictly nearer face, with the distances computed only where they matter.
    int c0, c1, r0, r1;
    for (std::size_t j = 0; j < corners_px.size(); ++j) {
        const auto& t = corners_px[j];
        const Eigen::Vector2d e1 = t[1] - t[0], e2 = t[2] - t[0];
        const double det = e1.x() * e2.y() - e1.y() * e2.x();
        if (!(std::abs(det) > 1e-12)) continue;  // no inside
        texelRange(t, 0.0, c0, c1, r0, r1);
        for (int r = r0; r <= r1; ++r) {
            for (int c = c0; c <= c1; ++c) {
                const Eigen::Vector2d q = Eigen::Vector2d(c + 0.5, r + 0.5) - t[0];
                const double b1 = (q.x() * e2.y() - q.y() * e2.x()) / det;
                const double b2 = (e1.x() * q.y() - e1.y() * q.x()) / det;
                const double b0 = 1.0 - b1 - b2;
                if (!(b0 >= 0 && b1 >= 0 && b2 >= 0)) continue;
                const std::size_t i = std::size_t(r) * std::size_t(w) + std::size_t(c);
                if (b0 > 1e-9 && b1 > 1e-9 && b2 > 1e-9) {
                    if (inside[i] >= 0) {
                        overlapping[static_cast<std::size_t>(inside[i])] = true;
                        overlapping[j] = true;
                    } else {
                        inside[i] = static_cast<std::int32_t>(j);
                    }
                }
                if (best[i] > 0) {
                    best[i] = 0;
                    owner[i] = static_cast<std::int32_t>(j);
                }
            }
        }
    }
    for (std::size_t j = 0; j < corners_px.size(); ++j) {
        const auto& t = corners_px[j];
        const Eigen::Vector2d lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]), hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
        texelRange(t, reach_px, c0, c1, r0, r1);
        for (int r = r0; r <= r1; ++r) {
            const double dy = std::max({lo.y() - (r + 0.5), 0.0, (r + 0.5) - hi.y()});
            for (int c = c0; c <= c1; ++c) {
                const std::size_t i = std::size_t(r) * std::size_t(w) + std::size_t(c);
                if (best[i] == 0) continue;
                // The face's box is no nearer than the face: skip what it cannot win.
                const double dx = std::max({lo.x() - (c + 0.5), 0.0, (c + 0.5) - hi.x()});
                const double box2 = dx * dx + dy * dy;
                if (box2 > reach2 || box2 >= best[i]) continue;
                const double d2 = nearestOnTriangle2(Eigen::Vector2d(c + 0.5, r + 0.5), t).distance2;
                if (d2 <= reach2 && d2 < best[i]) {
                    best[i] = d2;
                    owner[i] = static_cast<std::int32_t>(j);
                }
            }
        }
    }
    if (inside_out) {
        inside_out->resize(owner.size());
        for (std::size_t i = 0; i < owner.size(); ++i) (*inside_out)[i] = best[i] == 0 ? 1 : 0;
    }
    std::vector<std::uint32_t> out;
    for (std::size_t j = 0; j < overlapping.size(); ++j) {
        if (overlapping[j]) out.push_back(static_cast<std::uint32_t>(j));
    }
    return out;
}

}  // namespace vdbmap::tiles3d
