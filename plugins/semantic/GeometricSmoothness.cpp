// SPDX-License-Identifier: Apache-2.0
#include "GeometricSmoothness.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vdbmap/Error.h"

namespace vdbmap::semantic {

std::vector<float> geometricEdgeWeights(const std::vector<Vec3f>& vertices,
                                        const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                        const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                        const Vec3f& up_in,
                                        const GeometricSmoothnessOptions& options) {
    if (!(options.normal_sigma_deg > 0.0) || !(options.height_sigma_m > 0.0) ||
        !(options.min_weight > 0.0 && options.min_weight <= 1.0)) {
        throw InvalidInput("geometricEdgeWeights: need normal_sigma_deg > 0, height_sigma_m > 0 "
                           "and min_weight in (0, 1]");
    }
    const Vec3f up = up_in.normalized();
    const std::size_t n = triangles.size();
    std::vector<Vec3f> normal(n), centroid(n);
    for (std::size_t f = 0; f < n; ++f) {
        const auto& t = triangles[f];
        for (const std::uint32_t v : t) {
            if (v >= vertices.size()) {
                throw InvalidInput("geometricEdgeWeights: face " + std::to_string(f) +
                                   " refers to vertex " + std::to_string(v));
            }
        }
        const Vec3f& a = vertices[t[0]];
        const Vec3f& b = vertices[t[1]];
        const Vec3f& c = vertices[t[2]];
        const Vec3f cross = (b - a).cross(c - a);
        const float len = cross.norm();
        normal[f] = len > 0.0f ? Vec3f(cross / len) : up;
        centroid[f] = (a + b + c) / 3.0f;
    }
    const double sn = options.normal_sigma_deg * M_PI / 180.0;
    const double sh = options.height_sigma_m;
    std::vector<float> weights(adjacency.size());
    for (std::size_t e = 0; e < adjacency.size(); ++e) {
        const std::uint32_t i = adjacency[e][0], j = adjacency[e][1];
        if (i >= n || j >= n) {
            throw InvalidInput("geometricEdgeWeights: adjacency pair " + std::to_string(e) +
                               " is out of range");
        }
        const double cos_t = std::clamp(static_cast<double>(normal[i].dot(normal[j])), -1.0, 1.0);
        const double theta = std::acos(cos_t);
        const double level = std::min(std::abs(normal[i].dot(up)), std::abs(normal[j].dot(up)));
        const double h = std::abs(static_cast<double>((centroid[j] - centroid[i]).dot(up))) * level;
        const double w = std::exp(-theta * theta / (2 * sn * sn) - h * h / (2 * sh * sh));
        weights[e] = static_cast<float>(std::max(options.min_weight, w));
    }
    return weights;
}

void uniformBetweenObserved(std::vector<float>& weights,
                            const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                            const FaceVotes& votes) {
    if (weights.size() != adjacency.size()) {
        throw InvalidInput("uniformBetweenObserved: " + std::to_string(weights.size()) +
                           " weights for " + std::to_string(adjacency.size()) + " edges");
    }
    for (std::size_t e = 0; e < adjacency.size(); ++e) {
        const auto [i, j] = adjacency[e];
        if (i >= votes.numFaces() || j >= votes.numFaces()) {
            throw InvalidInput("uniformBetweenObserved: edge " + std::to_string(e) +
                               " is out of range of the votes");
        }
        if (votes.observed(i) && votes.observed(j)) weights[e] = 1.0f;
    }
}

}  // namespace vdbmap::semantic
