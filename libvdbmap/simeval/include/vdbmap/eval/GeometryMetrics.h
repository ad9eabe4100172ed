// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

class Raycaster;

/// Vertex positions and triangles of an OpenMesh mesh (deleted faces skipped; `face_index`,
/// if non-null, receives the OpenMesh face index of each triangle). Throws InvalidInput for a
/// non-triangle face.
void triMeshArrays(const TriMesh& mesh, std::vector<Vec3f>& vertices,
                   std::vector<std::array<std::uint32_t, 3>>& triangles,
                   std::vector<std::uint32_t>* face_index = nullptr);

/// Summary of a set of distances (metres).
struct DistanceStats {
    std::size_t count = 0;
    double mean = 0, median = 0, p90 = 0, max = 0, rms = 0;
};

/// Computes count, mean, median, 90th percentile, max and RMS (empty input: all zero).
DistanceStats distanceStats(std::vector<float> distances);

/// Options of the geometry evaluation.
struct GeometryEvalOptions {
    std::vector<double> tau_m{0.05, 0.1, 0.2};  ///< F-score thresholds
    /// Prediction surface samples: at most this spacing (metres), coarsened so that there are
    /// at most `max_samples` samples.
    double sample_spacing_m = 0.02;
    std::size_t max_samples = 2000000;
    /// A prediction sample farther than this from every observed ground-truth point is not
    /// scored for accuracy/precision (it lies on a surface the sensors never saw, e.g. the
    /// hole-filling of a large truncation behind an object, or outside the observed area).
    double observed_cutoff_m = 0.5;
    std::uint64_t seed = 1;
    /// Optional per ground-truth triangle flag (empty = all): only prediction samples and
    /// observed points whose nearest ground-truth triangle is flagged are scored, e.g. the
    /// faces of one class (the SUV without its ground plane).
    std::vector<char> gt_face_mask;
    /// Optional class id per ground-truth triangle (empty = none): completeness and recall are
    /// then also reported per class of the observed points' nearest ground-truth triangle
    /// (GeometryMetrics::per_class), e.g. the recall of the road and the sidewalk.
    std::vector<std::uint8_t> gt_face_class;
};

/// Completeness of the observed ground-truth points of one class.
struct ClassCompleteness {
    int class_id = 0;
    DistanceStats completeness;  ///< observed points of the class -> prediction mesh
    std::vector<double> recall;  ///< share of them within each tau (GeometryEvalOptions::tau_m)
};

/// Precision, recall and F-score at one threshold.
struct FScore {
    double tau_m = 0;
    double precision = 0, recall = 0, fscore = 0;
};

/// Geometry metrics of a predicted mesh against the ground truth.
struct GeometryMetrics {
    DistanceStats accuracy;      ///< prediction samples -> ground-truth mesh
    DistanceStats completeness;  ///< observed ground-truth points -> prediction mesh
    double chamfer_l1 = 0;       ///< (accuracy.mean + completeness.mean) / 2
    std::vector<FScore> fscores;
    std::size_t pred_samples = 0;       ///< samples drawn on the prediction
    std::size_t pred_samples_used = 0;  ///< of those, near observed ground truth (and masked in)
    std::size_t gt_points_used = 0;     ///< observed points scored for completeness
    std::size_t pred_faces = 0;
    /// Per class (ascending id), when GeometryEvalOptions::gt_face_class is given.
    std::vector<ClassCompleteness> per_class;
};

/// Area-uniform random samples on a triangle mesh (deterministic for `seed`): about
/// area / spacing^2 samples, at least one per triangle with positive area... on average.
std::vector<Vec3f> sampleSurface(const std::vector<Vec3f>& vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                 double spacing_m, std::uint64_t seed);

/// Evaluates `pred` (vertices + triangles) against the ground-truth mesh (`gt`, a Raycaster
/// on it) and the observed ground-truth points. Distances are exact point-to-triangle
/// distances (Embree point queries). An empty prediction gives accuracy count 0 and
/// completeness = the distance cap (1e3 m) for every point. If `pred_vertex_error` is
/// non-null it receives each prediction vertex's distance to the ground truth. Throws
/// InvalidInput for an empty tau list or a non-positive spacing.
GeometryMetrics evaluateGeometry(const std::vector<Vec3f>& pred_vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                 const Raycaster& gt, const std::vector<Vec3f>& gt_observed_points,
                                 const GeometryEvalOptions& options = {},
                                 std::vector<float>* pred_vertex_error = nullptr);

}  // namespace vdbmap
