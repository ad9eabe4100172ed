// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <memory>

#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

class VoxelMap;

/// Settings of the marching-cubes extraction.
struct MarchingCubesConfig {
    /// A cube is meshed only if all 8 corners are active in the tsdf with weight >= min_weight
    /// (and > 0): no faces between observed and unobserved space.
    double min_weight = 0.1;
    /// Connected components (sharing vertices) with fewer faces are removed; 0 keeps all.
    int min_component_faces = 0;
};

/// Counts of one extraction.
struct MeshStats {
    std::size_t cubes_meshed = 0;
    std::size_t faces = 0;
    std::size_t vertices = 0;
    std::size_t faces_removed_small_components = 0;
    std::size_t components_removed = 0;
    std::size_t faces_rejected_nonmanifold = 0;  ///< refused by OpenMesh (complex edge)
};

/// Marching cubes over the map's tsdf (zero level set, positive in front), parallel per leaf.
/// Vertices on shared cube edges are welded (one vertex per grid edge, deterministic order:
/// sorted by edge key), faces are oriented with their normal towards positive sdf, vertex
/// normals are area-weighted face normals. Positions in the world frame W, metres.
/// Grid coordinates must fit in [-2^19, 2^19) voxels per axis (edge keys are 62-bit).
std::shared_ptr<TriMesh> extractMesh(const VoxelMap& map, const MarchingCubesConfig& config,
                                     MeshStats* stats = nullptr);

}  // namespace vdbmap
