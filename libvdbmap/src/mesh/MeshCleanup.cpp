// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/mesh/MeshCleanup.h"

#include "vdbmap/core/UnionFind.h"

namespace vdbmap {
std::size_t removeSmallComponents(std::vector<std::array<std::uint32_t, 3>>& faces,
                                  std::size_t num_vertices, int min_faces,
                                  std::size_t* faces_removed) {
    if (faces_removed) *faces_removed = 0;
    if (min_faces <= 1 || faces.empty()) return 0;
    // Union-find over vertices: faces that share a vertex are in one component.
    std::vector<std::uint32_t> parent = makeDisjointSets(num_vertices);
    for (const auto& f : faces) {
        uniteSets(parent, f[0], f[1]);
        uniteSets(parent, f[0], f[2]);
    }
    std::vector<std::uint32_t> face_count(num_vertices, 0);
    for (const auto& f : faces) ++face_count[findRoot(parent, f[0])];
    std::size_t components_removed = 0;
    for (std::size_t v = 0; v < num_vertices; ++v)
        if (parent[v] == v && face_count[v] > 0 &&
            face_count[v] < static_cast<std::uint32_t>(min_faces))
            ++components_removed;
    std::size_t kept = 0;
    for (const auto& f : faces)
        if (face_count[findRoot(parent, f[0])] >= static_cast<std::uint32_t>(min_faces))
            faces[kept++] = f;
    if (faces_removed) *faces_removed = faces.size() - kept;
    faces.resize(kept);
    return components_removed;
}

}  // namespace vdbmap
