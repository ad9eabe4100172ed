// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace vdbmap::texture {

/// A texture patch (chart): faces that take the same view and touch each other through edges.
struct Patch {
    std::uint32_t view = 0;
    std::vector<std::uint32_t> faces;  ///< ascending
};

/// Connected components of the face adjacency restricted to edges whose faces share a label.
/// Faces labelled kNoLabel belong to no patch. Patches are ordered by their smallest face.
/// `face_patch` (optional) receives the patch of every face (kNoLabel if none).
std::vector<Patch> buildPatches(const std::vector<std::uint32_t>& face_labels,
                                const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                std::vector<std::uint32_t>* face_patch = nullptr);

}  // namespace vdbmap::texture
