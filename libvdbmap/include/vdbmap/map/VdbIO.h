// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>

namespace vdbmap {

class VoxelMap;

/// Writes map.vdb (DATA.md): float grid "surface" (signed distance, m, level set class),
/// float grid "weight" (both decoded from the packed TSDF), the truncation grid (when the map
/// was finalized by an integrator: metadata "truncation_max_m"), every extra grid, and metadata (voxel size,
/// truncation settings, creator "vdbmap <version>"). Atomic (temporary file + rename).
/// Throws IoError.
void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map);

/// The grids and the file metadata writeMapVdb writes, for callers that assemble map.vdb
/// from parts (a distributed run gathers each process's grids and writes them once).
openvdb::GridPtrVec mapVdbGrids(const VoxelMap& map);
openvdb::MetaMap mapVdbMetadata(const VoxelMap& map);
/// Writes `grids` and `meta` as a .vdb file, atomically. Throws IoError.
void writeVdbGrids(const std::filesystem::path& path, const openvdb::GridPtrVec& grids,
                   const openvdb::MetaMap& meta);

}  // namespace vdbmap
