// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

/// A triangle mesh as plain arrays (world frame W, metres): what ray casting, visibility,
/// texturing and evaluation use, so that they run and test without OpenMesh.
struct MeshArrays {
    std::vector<Vec3f> vertices_W;                   ///< vertex i = OpenMesh vertex idx i
    std::vector<std::array<std::uint32_t, 3>> faces;  ///< vertex indices of each triangle
    std::vector<std::uint32_t> face_index;           ///< OpenMesh face idx of each triangle
};

/// What meshArrays does with a face marked deleted (status) that garbage collection has not
/// removed yet.
enum class DeletedFaces {
    Skip,     ///< left out: triangle i is face `face_index[i]`
    Collapse  ///< kept, collapsed to its first vertex (zero area, never hit): triangle i = face i
};

/// Copies the vertices (every vertex slot) and the triangles of a TriMesh. Throws
/// InvalidInput naming the face when a face is not a triangle.
MeshArrays meshArrays(const TriMesh& mesh, DeletedFaces deleted = DeletedFaces::Skip);

}  // namespace vdbmap
