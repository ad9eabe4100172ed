// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/eval/SemanticMetrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

GtLabelTransfer transferGtLabels(const std::vector<Vec3f>& pred_vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                 const Raycaster& gt, const std::vector<std::uint8_t>& gt_labels,
                                 double max_distance_m, double stack_tolerance_m) {
    if (gt_labels.size() != gt.numTriangles()) {
        throw InvalidInput("evaluateSemantics: " + std::to_string(gt_labels.size()) +
                           " ground-truth labels for " + std::to_string(gt.numTriangles()) +
                           " faces");
    }
    const std::size_t n = pred_triangles.size();
    GtLabelTransfer t;
    t.label.assign(n, -1);
    t.area_m2.assign(n, 0.0);
    t.gt_point_W.assign(n, Vec3f::Zero());
    t.gt_face.assign(n, 0);
    std::vector<std::uint8_t> resolved(n, 0);
    const float stack_m = static_cast<float>(stack_tolerance_m);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f) {
            const auto& tri = pred_triangles[f];
            const Vec3f& a = pred_vertices[tri[0]];
            const Vec3f& b = pred_vertices[tri[1]];
            const Vec3f& c = pred_vertices[tri[2]];
            const Vec3f cross = (b - a).cross(c - a);
            const float cross_norm = cross.norm();
            t.area_m2[f] = 0.5 * static_cast<double>(cross_norm);
            const Vec3f centroid = (a + b + c) / 3.0f;
            const auto cp = gt.closestPoint(centroid, static_cast<float>(max_distance_m));
            if (!cp) continue;
            t.label[f] = gt_labels[cp->face];
            t.gt_point_W[f] = cp->point;
            t.gt_face[f] = cp->face;
            if (!(stack_m > 0.0f) || !(cross_norm > 0.0f)) continue;
            // Stacked surfaces: look at the ground truth from outside along the face normal.
            const Vec3f n_unit = cross / cross_norm;
            const float reach = cp->distance + stack_m;
            const auto hit = gt.intersect(centroid + reach * n_unit, -n_unit, 0.0f, 2.0f * reach);
            if (!hit || hit->face == cp->face) continue;
            // Within 2 * reach of the start, so at most stack_m farther than the nearest.
            const Vec3f p = centroid + (reach - hit->distance) * n_unit;
            if (gt_labels[hit->face] != gt_labels[cp->face]) resolved[f] = 1;
            t.label[f] = gt_labels[hit->face];
            t.gt_point_W[f] = p;
            t.gt_face[f] = hit->face;
        }
    });
    for (std::uint8_t r : resolved) t.stacked_resolved += r;
    return t;
}

SemanticMetrics scoreSemantics(const GtLabelTransfer& transfer,
                               const std::vector<std::uint8_t>& pred_labels,
                               const std::vector<std::uint8_t>* mask) {
    const std::size_t n = transfer.label.size();
    if (pred_labels.size() != n || transfer.area_m2.size() != n) {
        throw InvalidInput("evaluateSemantics: " + std::to_string(pred_labels.size()) +
                           " prediction labels for " + std::to_string(n) + " faces");
    }
    if (mask != nullptr && mask->size() != n) {
        throw InvalidInput("evaluateSemantics: face mask of size " +
                           std::to_string(mask->size()) + " for " + std::to_string(n) +
                           " faces");
    }
    // Sequential, deterministic area-weighted confusion matrix.
    std::vector<std::array<double, 256>> confusion(256);
    for (auto& row : confusion) row.fill(0.0);
    SemanticMetrics m;
    double correct = 0, unlabelled = 0;
    for (std::size_t f = 0; f < n; ++f) {
        if (mask != nullptr && (*mask)[f] == 0) continue;
        const double area = transfer.area_m2[f];
        const int gt_label = transfer.label[f];
        if (gt_label < 0) {
            m.unmatched_area_m2 += area;
            continue;
        }
        if (gt_label == 255) continue;
        m.matched_area_m2 += area;
        confusion[gt_label][pred_labels[f]] += area;
        if (pred_labels[f] == gt_label) correct += area;
        if (pred_labels[f] == 255) unlabelled += area;
    }
    if (m.matched_area_m2 > 0) {
        m.overall_accuracy = correct / m.matched_area_m2;
        m.unlabelled_fraction = unlabelled / m.matched_area_m2;
    }
    std::array<double, 256> col_sum{};
    for (int g = 0; g < 256; ++g) {
        for (int p = 0; p < 256; ++p) col_sum[p] += confusion[g][p];
    }
    for (int c = 0; c < 255; ++c) {
        double row = 0;
        for (int p = 0; p < 256; ++p) row += confusion[c][p];
        if (row <= 0) continue;
        ClassScore s;
        s.id = static_cast<std::uint8_t>(c);
        s.gt_area_m2 = row;
        s.accuracy = confusion[c][c] / row;
        s.iou = confusion[c][c] / (row + col_sum[c] - confusion[c][c]);
        for (int p = 0; p < 256; ++p) {
            if (p != c && confusion[c][p] > 0) {
                s.confused_m2.emplace_back(static_cast<std::uint8_t>(p), confusion[c][p]);
            }
        }
        std::stable_sort(s.confused_m2.begin(), s.confused_m2.end(),
                         [](const auto& a, const auto& b) { return a.second > b.second; });
        m.classes.push_back(s);
    }
    if (!m.classes.empty()) {
        for (const auto& s : m.classes) {
            m.mean_class_accuracy += s.accuracy;
            m.miou += s.iou;
        }
        m.mean_class_accuracy /= static_cast<double>(m.classes.size());
        m.miou /= static_cast<double>(m.classes.size());
    }
    return m;
}

SemanticMetrics evaluateSemantics(const std::vector<Vec3f>& pred_vertices,
                                  const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
                                  const std::vector<std::uint8_t>& pred_labels,
                                  const Raycaster& gt, const std::vector<std::uint8_t>& gt_labels,
                                  double max_distance_m) {
    if (pred_labels.size() != pred_triangles.size()) {
        throw InvalidInput("evaluateSemantics: " + std::to_string(pred_labels.size()) +
                           " prediction labels for " + std::to_string(pred_triangles.size()) +
                           " faces");
    }
    return scoreSemantics(
        transferGtLabels(pred_vertices, pred_triangles, gt, gt_labels, max_distance_m),
        pred_labels);
}

}  // namespace vdbmap
