// SPDX-License-Identifier: Apache-2.0
#include "TileMesh.h"

#include <string>

#include "vdbmap/Error.h"

namespace vdbmap::tiles3d {

void TileMesh::check() const {
    const std::size_t n = corners.size();
    if (label.size() != n || confidence.size() != n || page.size() != n ||
        (!uvs.empty() && uvs.size() != n)) {
        throw InvalidInput("tile mesh: per-face arrays disagree: " + std::to_string(n) +
                           " faces, " + std::to_string(label.size()) + " labels, " +
                           std::to_string(confidence.size()) + " confidences, " +
                           std::to_string(page.size()) + " pages, " + std::to_string(uvs.size()) +
                           " uv triples");
    }
    for (std::size_t f = 0; f < n; ++f) {
        if (page[f] != kNoPage && (page[f] >= pages.size() || uvs.empty())) {
            throw InvalidInput("tile mesh: face " + std::to_string(f) + " uses atlas page " +
                               std::to_string(page[f]) + " of " + std::to_string(pages.size()));
        }
    }
}

Bounds boundsW(const TileMesh& mesh) {
    Bounds b;
    for (std::size_t f = 0; f < mesh.faces(); ++f) {
        for (int k = 0; k < 3; ++k) b.add(mesh.cornerW(f, k));
    }
    return b;
}

std::array<double, 256> classAreas(const TileMesh& mesh) {
    std::array<double, 256> area{};
    for (std::size_t f = 0; f < mesh.faces(); ++f) {
        const auto& c = mesh.corners[f];
        area[mesh.label[f]] += 0.5 * static_cast<double>((c[1] - c[0]).cross(c[2] - c[0]).norm());
    }
    return area;
}

}  // namespace vdbmap::tiles3d
