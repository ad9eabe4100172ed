// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/eval/SemanticMetrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

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
    if (gt_labels.size() != gt.numTriangles()) {
        throw InvalidInput("evaluateSemantics: " + std::to_string(gt_labels.size()) +
                           " ground-truth labels for " + std::to_string(gt.numTriangles()) +
                           " faces");
    }
    // Nearest ground-truth face per prediction face (parallel), then a sequential,
    // deterministic area-weighted confusion matrix.
    std::vector<int> gt_label_of(pred_triangles.size(), -1);
    std::vector<double> area(pred_triangles.size(), 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pred_triangles.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t f = r.begin(); f != r.end(); ++f) {
                              const auto& t = pred_triangles[f];
                              const Vec3f& a = pred_vertices[t[0]];
                              const Vec3f& b = pred_vertices[t[1]];
                              const Vec3f& c = pred_vertices[t[2]];
                              area[f] = 0.5 * static_cast<double>((b - a).cross(c - a).norm());
                              const Vec3f centroid = (a + b + c) / 3.0f;
                              if (auto cp = gt.closestPoint(centroid,
                                                            static_cast<float>(max_distance_m))) {
                                  gt_label_of[f] = gt_labels[cp->face];
                              }
                          }
                      });
    std::vector<std::array<double, 256>> confusion(256);
    for (auto& row : confusion) row.fill(0.0);
    SemanticMetrics m;
    double correct = 0, unlabelled = 0;
    for (std::size_t f = 0; f < pred_triangles.size(); ++f) {
        if (gt_label_of[f] < 0) {
            m.unmatched_area_m2 += area[f];
            continue;
        }
        if (gt_label_of[f] == 255) continue;
        m.matched_area_m2 += area[f];
        confusion[gt_label_of[f]][pred_labels[f]] += area[f];
        if (pred_labels[f] == gt_label_of[f]) correct += area[f];
        if (pred_labels[f] == 255) unlabelled += area[f];
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

}  // namespace vdbmap
