// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
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
    std::size_t halo_faces = 0;                  ///< extractMeshRegion: faces of halo cubes
};

/// Marching cubes over the map's tsdf (zero level set, positive in front), parallel per leaf.
/// Vertices on shared cube edges are welded (one vertex per grid edge, deterministic order:
/// sorted by edge key), faces are oriented with their normal towards positive sdf, vertex
/// normals are area-weighted face normals. Positions in the world frame W, metres.
/// Grid coordinates must fit in [-2^19, 2^19) voxels per axis (edge keys are 62-bit).
std::shared_ptr<TriMesh> extractMesh(const VoxelMap& map, const MarchingCubesConfig& config,
                                     MeshStats* stats = nullptr);

/// A ground region of the map in voxel coordinates: the cubes whose min corner, projected on
/// the two ground axes, lies in [core_min, core_max) form its core, those within `halo_vox`
/// voxels of the core its halo; the third (up) axis is unbounded. A cube belongs to the core of
/// exactly one region of a partition of the ground, so the core faces of a partition's regions
/// are the faces of extractMesh.
struct MeshRegion {
    int axes[2] = {0, 1};  ///< the ground axes (0 = x, 1 = y, 2 = z), e.g. {0, 2} if y is up
    std::int32_t core_min[2] = {0, 0};
    std::int32_t core_max[2] = {0, 0};  ///< exclusive
    std::int32_t halo_vox = 0;
    bool inCore(std::int32_t x, std::int32_t y) const {
        return x >= core_min[0] && x < core_max[0] && y >= core_min[1] && y < core_max[1];
    }
    bool inRegion(std::int32_t x, std::int32_t y) const {
        return x >= core_min[0] - halo_vox && x < core_max[0] + halo_vox &&
               y >= core_min[1] - halo_vox && y < core_max[1] + halo_vox;
    }
};

/// extractMesh restricted to the cubes of `region` (core and halo). Each face of a halo cube
/// is marked in the face property kHaloFaceProperty (vdbmap/mesh/TileFaces.h); core faces are
/// exactly the faces extractMesh gives for those cubes, at the same float positions. Small
/// components (config.min_component_faces) are measured on core + halo.
std::shared_ptr<TriMesh> extractMeshRegion(const VoxelMap& map, const MarchingCubesConfig& config,
                                           const MeshRegion& region, MeshStats* stats = nullptr);

}  // namespace vdbmap
