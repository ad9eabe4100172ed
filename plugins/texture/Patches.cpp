// SPDX-License-Identifier: Apache-2.0
#include "Patches.h"

#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"
#include "vdbmap/core/UnionFind.h"

namespace vdbmap::texture {

std::vector<Patch> buildPatches(const std::vector<std::uint32_t>& face_labels,
                                const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                std::vector<std::uint32_t>* face_patch) {
    const std::size_t num_faces = face_labels.size();
    std::vector<std::uint32_t> parent = makeDisjointSets(num_faces);
    for (const auto& [a, b] : adjacency) {
        if (a >= num_faces || b >= num_faces) {
            throw InvalidInput("texture: adjacency refers to face " +
                               std::to_string(std::max(a, b)) + " of " + std::to_string(num_faces));
        }
        if (face_labels[a] == kNoLabel || face_labels[a] != face_labels[b]) continue;
        // The smaller index becomes the root, so roots are the smallest face of each patch.
        uniteSets(parent, a, b);
    }
    std::vector<Patch> patches;
    std::vector<std::uint32_t> patch_of_root(num_faces, kNoLabel);
    if (face_patch) face_patch->assign(num_faces, kNoLabel);
    for (std::uint32_t f = 0; f < num_faces; ++f) {
        if (face_labels[f] == kNoLabel) continue;
        const std::uint32_t root = findRoot(parent, f);
        if (patch_of_root[root] == kNoLabel) {
            patch_of_root[root] = static_cast<std::uint32_t>(patches.size());
            patches.push_back({face_labels[f], {}});
        }
        patches[patch_of_root[root]].faces.push_back(f);
        if (face_patch) (*face_patch)[f] = patch_of_root[root];
    }
    return patches;
}

}  // namespace vdbmap::texture
