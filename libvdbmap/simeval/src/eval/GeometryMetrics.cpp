// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/eval/GeometryMetrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "vdbmap/Error.h"
#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

namespace {

constexpr float kDistanceCap = 1000.0f;

std::vector<float> distancesTo(const Raycaster& target, const std::vector<Vec3f>& points) {
    std::vector<float> out(points.size(), kDistanceCap);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 512),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              if (auto cp = target.closestPoint(points[i], kDistanceCap)) {
                                  out[i] = cp->distance;
                              }
                          }
                      });
    return out;
}

double triangleArea(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    return 0.5 * static_cast<double>((b - a).cross(c - a).norm());
}

double shareBelow(const std::vector<float>& d, double tau) {
    if (d.empty()) return 0.0;
    return static_cast<double>(std::count_if(d.begin(), d.end(), [&](float x) { return x < tau; })) /
           static_cast<double>(d.size());
}

std::vector<ClassCompleteness> perClassCompleteness(const std::vector<int>& point_class,
                                                    const std::vector<float>& comp,
                                                    const std::vector<double>& tau_m) {
    std::vector<std::vector<float>> by_class(256);
    for (std::size_t i = 0; i < comp.size(); ++i)
        if (point_class[i] >= 0 && point_class[i] < 256)
            by_class[static_cast<std::size_t>(point_class[i])].push_back(comp[i]);
    std::vector<ClassCompleteness> out;
    for (std::size_t c = 0; c < by_class.size(); ++c) {
        if (by_class[c].empty()) continue;
        ClassCompleteness cc;
        cc.class_id = static_cast<int>(c);
        for (double tau : tau_m) cc.recall.push_back(shareBelow(by_class[c], tau));
        cc.completeness = distanceStats(std::move(by_class[c]));
        out.push_back(std::move(cc));
    }
    return out;
}

}  // namespace

void triMeshArrays(const TriMesh& mesh, std::vector<Vec3f>& vertices,
                   std::vector<std::array<std::uint32_t, 3>>& triangles,
                   std::vector<std::uint32_t>* face_index) {
    MeshArrays arrays = meshArrays(mesh, DeletedFaces::Skip);
    vertices = std::move(arrays.vertices_W);
    triangles = std::move(arrays.faces);
    if (face_index) *face_index = std::move(arrays.face_index);
}

DistanceStats distanceStats(std::vector<float> d) {
    DistanceStats s;
    s.count = d.size();
    if (d.empty()) return s;
    double sum = 0, sum2 = 0;
    for (float x : d) {
        sum += x;
        sum2 += static_cast<double>(x) * x;
    }
    s.mean = sum / d.size();
    s.rms = std::sqrt(sum2 / d.size());
    auto quantile = [&](double q) {
        const std::size_t k = std::min(d.size() - 1, static_cast<std::size_t>(q * (d.size() - 1) + 0.5));
        std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(k), d.end());
        return static_cast<double>(d[k]);
    };
    s.median = quantile(0.5);
    s.p90 = quantile(0.9);
    s.max = *std::max_element(d.begin(), d.end());
    return s;
}

std::vector<Vec3f> sampleSurface(const std::vector<Vec3f>& vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                 double spacing_m, std::uint64_t seed) {
    if (!(spacing_m > 0)) {
        throw InvalidInput("sampleSurface: spacing must be > 0, got " + std::to_string(spacing_m));
    }
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<Vec3f> out;
    const double per_m2 = 1.0 / (spacing_m * spacing_m);
    for (const auto& t : triangles) {
        const Vec3f& a = vertices[t[0]];
        const Vec3f& b = vertices[t[1]];
        const Vec3f& c = vertices[t[2]];
        const double expected = triangleArea(a, b, c) * per_m2;
        auto n = static_cast<std::size_t>(std::floor(expected));
        if (uni(rng) < expected - std::floor(expected)) ++n;
        for (std::size_t i = 0; i < n; ++i) {
            double r1 = uni(rng), r2 = uni(rng);
            if (r1 + r2 > 1.0) {
                r1 = 1.0 - r1;
                r2 = 1.0 - r2;
            }
            out.push_back(a + static_cast<float>(r1) * (b - a) + static_cast<float>(r2) * (c - a));
        }
    }
    return out;
}

GeometryMetrics evaluateGeometry(const std::vector<Vec3f>& pred_vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                 const Raycaster& gt, const std::vector<Vec3f>& gt_observed_points,
                                 const GeometryEvalOptions& options,
                                 std::vector<float>* pred_vertex_error) {
    if (options.tau_m.empty()) throw InvalidInput("evaluateGeometry: empty tau list");
    for (double tau : options.tau_m) {
        if (!(tau > 0)) {
            throw InvalidInput("evaluateGeometry: tau must be > 0, got " + std::to_string(tau));
        }
    }
    GeometryMetrics m;
    m.pred_faces = pred_triangles.size();
    double area = 0;
    for (const auto& t : pred_triangles) {
        area += triangleArea(pred_vertices[t[0]], pred_vertices[t[1]], pred_vertices[t[2]]);
    }
    const double spacing =
        std::max(options.sample_spacing_m,
                 std::sqrt(area / static_cast<double>(std::max<std::size_t>(1, options.max_samples))));
    std::vector<Vec3f> samples = sampleSurface(pred_vertices, pred_triangles, spacing, options.seed);
    m.pred_samples = samples.size();

    // Restrict accuracy to the observed part: a Raycaster over point "triangles" gives the
    // nearest observed ground-truth point.
    std::vector<std::array<std::uint32_t, 3>> point_tris(gt_observed_points.size());
    for (std::size_t i = 0; i < point_tris.size(); ++i) {
        const auto k = static_cast<std::uint32_t>(i);
        point_tris[i] = {k, k, k};
    }
    const Raycaster observed(gt_observed_points, point_tris);
    std::vector<char> keep(samples.size(), 1);
    if (!gt_observed_points.empty()) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size(), 512),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                  keep[i] = observed
                                                .closestPoint(samples[i],
                                                              static_cast<float>(options.observed_cutoff_m))
                                                .has_value();
                              }
                          });
    }
    const std::vector<char>& mask = options.gt_face_mask;
    if (!mask.empty() && mask.size() != gt.numTriangles()) {
        throw InvalidInput("evaluateGeometry: face mask has " + std::to_string(mask.size()) +
                           " entries for " + std::to_string(gt.numTriangles()) +
                           " ground-truth triangles");
    }
    // Distances to the ground truth, and whether the nearest ground-truth face is masked in.
    auto toGt = [&](const std::vector<Vec3f>& points, const std::vector<char>& pre_keep,
                    std::vector<float>& d) {
        std::vector<char> in(points.size(), 0);
        d.assign(points.size(), kDistanceCap);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 512),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                  if (!pre_keep.empty() && !pre_keep[i]) continue;
                                  if (auto cp = gt.closestPoint(points[i], kDistanceCap)) {
                                      d[i] = cp->distance;
                                      in[i] = mask.empty() || mask[cp->face];
                                  }
                              }
                          });
        return in;
    };
    std::vector<float> sample_d;
    const std::vector<char> sample_in = toGt(samples, keep, sample_d);
    std::vector<float> acc;
    acc.reserve(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (keep[i] && sample_in[i]) acc.push_back(sample_d[i]);
    }
    m.pred_samples_used = acc.size();

    const std::vector<std::uint8_t>& face_class = options.gt_face_class;
    if (!face_class.empty() && face_class.size() != gt.numTriangles()) {
        throw InvalidInput("evaluateGeometry: face classes have " + std::to_string(face_class.size()) +
                           " entries for " + std::to_string(gt.numTriangles()) +
                           " ground-truth triangles");
    }
    std::vector<Vec3f> gt_points;
    if (mask.empty()) {
        gt_points = gt_observed_points;
    } else {
        std::vector<float> unused;
        const std::vector<char> point_in = toGt(gt_observed_points, {}, unused);
        for (std::size_t i = 0; i < gt_observed_points.size(); ++i) {
            if (point_in[i]) gt_points.push_back(gt_observed_points[i]);
        }
    }
    // The class of each scored observed point: that of its nearest ground-truth triangle.
    std::vector<int> point_class;
    if (!face_class.empty()) {
        point_class.assign(gt_points.size(), -1);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, gt_points.size(), 512),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i)
                                  if (auto cp = gt.closestPoint(gt_points[i], kDistanceCap))
                                      point_class[i] = face_class[cp->face];
                          });
    }
    m.gt_points_used = gt_points.size();
    std::vector<float> comp(gt_points.size(), kDistanceCap);
    if (!pred_triangles.empty()) {
        const Raycaster pred(pred_vertices, pred_triangles);
        comp = distancesTo(pred, gt_points);
    }
    for (double tau : options.tau_m) {
        FScore f;
        f.tau_m = tau;
        const auto below = [&](const std::vector<float>& d) {
            if (d.empty()) return 0.0;
            return static_cast<double>(std::count_if(d.begin(), d.end(),
                                                     [&](float x) { return x < tau; })) /
                   static_cast<double>(d.size());
        };
        f.precision = below(acc);
        f.recall = below(comp);
        f.fscore = f.precision + f.recall > 0
                       ? 2 * f.precision * f.recall / (f.precision + f.recall)
                       : 0.0;
        m.fscores.push_back(f);
    }
    if (!point_class.empty()) m.per_class = perClassCompleteness(point_class, comp, options.tau_m);
    m.accuracy = distanceStats(acc);
    m.completeness = distanceStats(comp);
    m.chamfer_l1 = 0.5 * (m.accuracy.mean + m.completeness.mean);
    if (pred_vertex_error) *pred_vertex_error = distancesTo(gt, pred_vertices);
    return m;
}

}  // namespace vdbmap
