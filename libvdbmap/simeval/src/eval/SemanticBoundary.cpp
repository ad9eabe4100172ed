// SPDX-License-Identifier: Apache-2.0
// Errors at ground-truth class boundaries vs inside a class, and unknown faces next to known
// ones (issue #6: no unlabelled face may have a labelled neighbour).
#include "vdbmap/eval/SemanticBoundary.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {
namespace {

/// The ground-truth class at `q` seen along the unit normal `n` (see transferGtLabels), or -1.
int gtClassAt(const Vec3f& q, const Vec3f& n, const Raycaster& gt,
              const std::vector<std::uint8_t>& gt_labels, float max_distance, float stack_m) {
    const auto cp = gt.closestPoint(q, max_distance);
    if (!cp) return -1;
    int label = gt_labels[cp->face];
    if (stack_m > 0.0f) {
        const float reach = cp->distance + stack_m;
        const auto hit = gt.intersect(q + reach * n, -n, 0.0f, 2.0f * reach);
        if (hit) label = gt_labels[hit->face];
    }
    return label;
}

}  // namespace

std::vector<std::uint8_t> nearGtClassBoundary(
    const std::vector<Vec3f>& pred_vertices,
    const std::vector<std::array<std::uint32_t, 3>>& pred_triangles,
    const GtLabelTransfer& transfer, const Raycaster& gt,
    const std::vector<std::uint8_t>& gt_labels, double radius_m, double max_distance_m,
    double stack_tolerance_m) {
    if (gt_labels.size() != gt.numTriangles()) {
        throw InvalidInput("nearGtClassBoundary: " + std::to_string(gt_labels.size()) +
                           " ground-truth labels for " + std::to_string(gt.numTriangles()) +
                           " faces");
    }
    const std::size_t n = pred_triangles.size();
    if (transfer.label.size() != n || transfer.gt_point_W.size() != n) {
        throw InvalidInput("nearGtClassBoundary: a transfer of " +
                           std::to_string(transfer.label.size()) + " faces for " +
                           std::to_string(n) + " triangles");
    }
    if (!(radius_m > 0.0)) {
        throw InvalidInput("nearGtClassBoundary: radius_m must be > 0, got " +
                           std::to_string(radius_m));
    }
    const float radius = static_cast<float>(radius_m);
    const float max_distance = static_cast<float>(max_distance_m);
    const float stack_m = static_cast<float>(stack_tolerance_m);
    std::vector<std::uint8_t> near(n, 0);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t f = r.begin(); f != r.end(); ++f) {
                if (transfer.label[f] < 0) continue;
                const auto& tri = pred_triangles[f];
                const Vec3f& a = pred_vertices[tri[0]];
                const Vec3f cross = (pred_vertices[tri[1]] - a).cross(pred_vertices[tri[2]] - a);
                if (!(cross.norm() > 0.0f)) continue;
                const Vec3f normal = cross.normalized();
                // Two unit vectors spanning the face's plane.
                const Vec3f u = normal.unitOrthogonal();
                const Vec3f v = normal.cross(u);
                for (int k = 0; k < 8 && near[f] == 0; ++k) {
                    const float angle = static_cast<float>(k * M_PI / 4.0);
                    const Vec3f q = transfer.gt_point_W[f] +
                                    radius * (std::cos(angle) * u + std::sin(angle) * v);
                    const int label = gtClassAt(q, normal, gt, gt_labels, max_distance, stack_m);
                    if (label >= 0 && label != transfer.label[f]) near[f] = 1;
                }
            }
        });
    return near;
}

std::size_t unlabelledNextToLabelled(const std::vector<std::uint8_t>& face_labels,
                                     const std::vector<std::array<std::uint32_t, 2>>& adjacency) {
    constexpr std::uint8_t kUnknown = 255;
    std::vector<std::uint8_t> flagged(face_labels.size(), 0);
    for (const auto& e : adjacency) {
        if (e[0] >= face_labels.size() || e[1] >= face_labels.size()) {
            throw InvalidInput("unlabelledNextToLabelled: adjacency pair (" + std::to_string(e[0]) +
                               ", " + std::to_string(e[1]) + ") out of range for " +
                               std::to_string(face_labels.size()) + " faces");
        }
        const bool u0 = face_labels[e[0]] == kUnknown, u1 = face_labels[e[1]] == kUnknown;
        if (u0 && !u1) flagged[e[0]] = 1;
        if (u1 && !u0) flagged[e[1]] = 1;
    }
    std::size_t count = 0;
    for (const std::uint8_t f : flagged) count += f;
    return count;
}

}  // namespace vdbmap
