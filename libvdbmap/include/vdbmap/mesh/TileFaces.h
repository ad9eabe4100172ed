// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

/// Name of the bool face property marking the halo faces of a tile's mesh: faces a tile sees
/// (and lets take part in coupled decisions such as MRFs) but does not own. Meshes without the
/// property have no halo faces.
inline constexpr const char* kHaloFaceProperty = "tile_halo";

/// One flag per face (1 = halo); all 0 when the mesh has no halo property.
std::vector<std::uint8_t> haloFaceMask(const TriMesh& mesh);

/// Sets the halo property from one flag per face (adds the property if needed).
void setHaloFaceMask(TriMesh& mesh, const std::vector<std::uint8_t>& halo);

/// The mesh's core (non-halo) faces with the vertices they use, in face order;
/// `core_faces` (if given) receives the source face index of each face of the result.
TriMesh coreSubmesh(const TriMesh& mesh, std::vector<std::uint32_t>* core_faces = nullptr);

}  // namespace vdbmap
