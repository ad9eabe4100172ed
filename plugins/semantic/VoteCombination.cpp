// SPDX-License-Identifier: Apache-2.0
#include "VoteCombination.h"

#include <algorithm>
#include <cstdint>
#include <string>

#include "vdbmap/Error.h"

namespace vdbmap::semantic {

namespace {

// Sum of a face's weights.
double mass(const FaceVotes& v, std::size_t f) {
    double total = 0.0;
    for (std::uint64_t k = v.offsets[f]; k < v.offsets[f + 1]; ++k) total += v.weights[k];
    return total;
}

}  // namespace

FaceVotes combineVotes(const FaceVotes& images, const FaceVotes& lidar, double lidar_weight,
                       std::vector<std::uint8_t>* sources) {
    if (!(lidar_weight >= 0.0)) {
        throw InvalidInput("combineVotes: lidar_weight must be >= 0, got " +
                           std::to_string(lidar_weight));
    }
    const bool has_i = images.numFaces() > 0, has_l = lidar.numFaces() > 0;
    if (has_i && has_l &&
        (images.numFaces() != lidar.numFaces() || images.num_classes != lidar.num_classes)) {
        throw InvalidInput("combineVotes: image votes for " + std::to_string(images.numFaces()) +
                           " faces x " + std::to_string(images.num_classes) +
                           " classes, LiDAR votes for " + std::to_string(lidar.numFaces()) +
                           " x " + std::to_string(lidar.num_classes));
    }
    const FaceVotes& shape = has_i ? images : lidar;
    const std::size_t n_faces = shape.numFaces();
    FaceVotes out;
    out.num_classes = shape.num_classes;
    out.votes = images.votes + lidar.votes;
    out.void_votes = images.void_votes + lidar.void_votes;
    out.unknown_id_votes = images.unknown_id_votes + lidar.unknown_id_votes;
    out.offsets.reserve(n_faces + 1);
    out.offsets.push_back(0);
    if (sources != nullptr) sources->assign(n_faces, kSourceNone);
    for (std::size_t f = 0; f < n_faces; ++f) {
        const double m_i = has_i ? mass(images, f) : 0.0;
        const double m_l = has_l ? mass(lidar, f) : 0.0;
        const double a_i = m_i > 0.0 ? 1.0 : 0.0;
        const double a_l = m_l > 0.0 ? lidar_weight : 0.0;
        if (sources != nullptr) {
            (*sources)[f] = static_cast<std::uint8_t>((m_i > 0.0 ? kSourceImages : 0) |
                                                      (m_l > 0.0 ? kSourceLidar : 0));
        }
        const double norm = a_i + a_l;
        if (norm <= 0.0) {
            // Only a source with weight 0 saw it (or none): no data for the MRF.
            out.offsets.push_back(out.classes.size());
            continue;
        }
        // Merge the two class-ascending lists.
        std::uint64_t ki = has_i ? images.offsets[f] : 0, ei = has_i ? images.offsets[f + 1] : 0;
        std::uint64_t kl = has_l ? lidar.offsets[f] : 0, el = has_l ? lidar.offsets[f + 1] : 0;
        while (ki < ei || kl < el) {
            const std::uint32_t ci = ki < ei ? images.classes[ki] : UINT32_MAX;
            const std::uint32_t cl = kl < el ? lidar.classes[kl] : UINT32_MAX;
            const std::uint32_t c = std::min(ci, cl);
            double p = 0.0;
            if (ci == c) p += a_i * images.weights[ki++] / m_i;
            if (cl == c) p += a_l * lidar.weights[kl++] / m_l;
            if (p > 0.0) {
                out.classes.push_back(c);
                out.weights.push_back(static_cast<float>(p / norm));
            }
        }
        out.offsets.push_back(out.classes.size());
    }
    return out;
}

}  // namespace vdbmap::semantic
