// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/mesh/MeshAdjacency.h"

#include <algorithm>

namespace vdbmap {

std::vector<std::array<std::uint32_t, 2>> faceAdjacency(const TriMesh& mesh) {
    std::vector<std::array<std::uint32_t, 2>> pairs;
    pairs.reserve(mesh.n_edges());
    for (const auto eh : mesh.edges()) {
        if (mesh.has_edge_status() && mesh.status(eh).deleted()) continue;
        const auto h0 = mesh.halfedge_handle(eh, 0);
        const auto h1 = mesh.halfedge_handle(eh, 1);
        const auto f0 = mesh.face_handle(h0);
        const auto f1 = mesh.face_handle(h1);
        if (!f0.is_valid() || !f1.is_valid()) continue;  // boundary edge
        if (mesh.has_face_status() &&
            (mesh.status(f0).deleted() || mesh.status(f1).deleted())) {
            continue;
        }
        const auto a = static_cast<std::uint32_t>(f0.idx());
        const auto b = static_cast<std::uint32_t>(f1.idx());
        if (a == b) continue;
        pairs.push_back({std::min(a, b), std::max(a, b)});
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    return pairs;
}

}  // namespace vdbmap
