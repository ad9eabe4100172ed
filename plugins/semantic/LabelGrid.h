// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"

#include <cstdint>
#include <vector>

#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap::semantic {

/// A FloatGrid with the class id of the nearest face in every voxel within `band_vox` voxels
/// of the mesh (background 255 = unknown), on `transform` (the map's). Float, not Int32,
/// because Blender's volume import reads float grids only; ids are exact in a float. Uses
/// OpenVDB's meshToVolume with its closest-polygon index grid. Throws InvalidInput if
/// `face_labels` does not match the mesh or band_vox < 1. An empty mesh gives an empty grid.
openvdb::FloatGrid::Ptr labelGrid(const TriMesh& mesh, const std::vector<std::uint8_t>& face_labels,
                                  const openvdb::math::Transform& transform, float band_vox);

}  // namespace vdbmap::semantic
