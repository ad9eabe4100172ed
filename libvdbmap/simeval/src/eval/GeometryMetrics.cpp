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

namespace {

void checkOptions(const GeometryEvalOptions& options, const Raycaster& gt) {
    if (options.tau_m.empty()) throw InvalidInput("evaluateGeometry: empty tau list");
    for (double tau : options.tau_m) {
        if (!(tau > 0)) {
            throw InvalidInput("evaluateGeometry: tau must be > 0, got " + std::to_string(tau));
        }
    }
    const auto checkSize = [&](std::size_t n, const char* what) {
        if (n != 0 && n != gt.numTriangles()) {
            throw InvalidInput("evaluateGeometry: " + std::string(what) + " have " +
                               std::to_string(n) + " entries for " +
                               std::to_string(gt.numTriangles()) + " ground-truth triangles");
        }
    };
    checkSize(options.gt_face_mask.size(), "face mask");
    checkSize(options.gt_face_class.size(), "face classes");
}

// Area-uniform samples of the predicted mesh, at most options.max_samples of them.
std::vector<Vec3f> predictionSamples(const std::vector<Vec3f>& vertices,
                                     const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                     const GeometryEvalOptions& options) {
    double area = 0;
    for (const auto& t : triangles) area += triangleArea(vertices[t[0]], vertices[t[1]], vertices[t[2]]);
    const double spacing = std::max(
        options.sample_spacing_m,
        std::sqrt(area / static_cast<double>(std::max<std::size_t>(1, options.max_samples))));
    return sampleSurface(vertices, triangles, spacing, options.seed);
}

// 1 for the samples within the cutoff of an observed ground-truth point (accuracy is scored on
// the observed part only; a Raycaster over point "triangles" finds the nearest point).
std::vector<char> nearObserved(const std::vector<Vec3f>& samples,
                               const std::vector<Vec3f>& observed_points, double cutoff_m) {
    std::vector<char> keep(samples.size(), 1);
    if (observed_points.empty()) return keep;
    std::vector<std::array<std::uint32_t, 3>> point_tris(observed_points.size());
    for (std::size_t i = 0; i < point_tris.size(); ++i) {
        const auto k = static_cast<std::uint32_t>(i);
        point_tris[i] = {k, k, k};
    }
    const Raycaster observed(observed_points, point_tris);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size(), 512),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              keep[i] = observed.closestPoint(samples[i], static_cast<float>(cutoff_m))
                                            .has_value();
                          }
                      });
    return keep;
}

// Distances of `points` (those with `pre_keep`, all if it is empty) to the ground truth into
// `d`, and per point its nearest ground-truth face (-1: none within the cap).
std::vector<std::int64_t> nearestGtFaces(const Raycaster& gt, const std::vector<Vec3f>& points,
                                         const std::vector<char>& pre_keep, std::vector<float>& d) {
    std::vector<std::int64_t> face(points.size(), -1);
    d.assign(points.size(), kDistanceCap);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 512),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              if (!pre_keep.empty() && !pre_keep[i]) continue;
                              if (auto cp = gt.closestPoint(points[i], kDistanceCap)) {
                                  d[i] = cp->distance;
                                  face[i] = static_cast<std::int64_t>(cp->face);
                              }
                          }
                      });
    return face;
}

bool maskedIn(const std::vector<char>& mask, std::int64_t face) {
    return face >= 0 && (mask.empty() || mask[static_cast<std::size_t>(face)]);
}

// Accuracy distances: the kept samples whose nearest ground-truth face is masked in.
std::vector<float> accuracyDistances(const Raycaster& gt, const std::vector<Vec3f>& samples,
                                     const std::vector<char>& keep, const std::vector<char>& mask) {
    std::vector<float> d;
    const std::vector<std::int64_t> face = nearestGtFaces(gt, samples, keep, d);
    std::vector<float> acc;
    acc.reserve(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (keep[i] && maskedIn(mask, face[i])) acc.push_back(d[i]);
    }
    return acc;
}

// The observed points completeness scores (those whose nearest ground-truth face is masked in)
// and, with face classes, the class of each (that of its nearest face; -1 none).
void scoredGtPoints(const Raycaster& gt, const std::vector<Vec3f>& observed_points,
                    const GeometryEvalOptions& options, std::vector<Vec3f>& points,
                    std::vector<int>& point_class) {
    const std::vector<char>& mask = options.gt_face_mask;
    const std::vector<std::uint8_t>& face_class = options.gt_face_class;
    points.clear();
    point_class.clear();
    if (mask.empty() && face_class.empty()) {
        points = observed_points;
        return;
    }
    std::vector<float> unused;
    const std::vector<std::int64_t> face = nearestGtFaces(gt, observed_points, {}, unused);
    for (std::size_t i = 0; i < observed_points.size(); ++i) {
        if (!mask.empty() && !maskedIn(mask, face[i])) continue;
        points.push_back(observed_points[i]);
        if (!face_class.empty()) {
            point_class.push_back(face[i] >= 0 ? face_class[static_cast<std::size_t>(face[i])] : -1);
        }
    }
}

std::vector<FScore> fscores(const std::vector<float>& acc, const std::vector<float>& comp,
                            const std::vector<double>& tau_m) {
    std::vector<FScore> out;
    for (double tau : tau_m) {
        FScore f;
        f.tau_m = tau;
        f.precision = shareBelow(acc, tau);
        f.recall = shareBelow(comp, tau);
        f.fscore = f.precision + f.recall > 0
                       ? 2 * f.precision * f.recall / (f.precision + f.recall)
                       : 0.0;
        out.push_back(f);
    }
    return out;
}

}  // namespace

GeometryMetrics evaluateGeometry(const std::vector<Vec3f>& pred_vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                 const Raycaster& gt, const std::vector<Vec3f>& gt_observed_points,
                                 const GeometryEvalOptions& options,
                                 std::vector<float>* pred_vertex_error) {
    checkOptions(options, gt);
    GeometryMetrics m;
    m.pred_faces = pred_triangles.size();

    // Accuracy (prediction -> ground truth) on the observed part.
    const std::vector<Vec3f> samples = predictionSamples(pred_vertices, pred_triangles, options);
    m.pred_samples = samples.size();
    const std::vector<char> keep =
        nearObserved(samples, gt_observed_points, options.observed_cutoff_m);
    const std::vector<float> acc = accuracyDistances(gt, samples, keep, options.gt_face_mask);
    m.pred_samples_used = acc.size();

    // Completeness (observed ground truth -> prediction).
    std::vector<Vec3f> gt_points;
    std::vector<int> point_class;
    scoredGtPoints(gt, gt_observed_points, options, gt_points, point_class);
    m.gt_points_used = gt_points.size();
    std::vector<float> comp(gt_points.size(), kDistanceCap);
    if (!pred_triangles.empty()) comp = distancesTo(Raycaster(pred_vertices, pred_triangles), gt_points);

    m.fscores = fscores(acc, comp, options.tau_m);
    if (!point_class.empty()) m.per_class = perClassCompleteness(point_class, comp, options.tau_m);
    m.accuracy = distanceStats(acc);
    m.completeness = distanceStats(comp);
    m.chamfer_l1 = 0.5 * (m.accuracy.mean + m.completeness.mean);
    if (pred_vertex_error) *pred_vertex_error = distancesTo(gt, pred_vertices);
    return m;
}

}  // namespace vdbmap
