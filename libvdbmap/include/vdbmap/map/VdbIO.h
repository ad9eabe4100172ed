// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>

namespace vdbmap {

class VoxelMap;

/// Writes map.vdb (DATA.md): float grid "surface" (signed distance, m, level set class),
/// float grid "weight" (both decoded from the packed TSDF), the truncation grid (when the map
/// was finalized by an integrator: metadata "truncation_max_m"), every extra grid, and metadata (voxel size,
/// truncation settings, creator "vdbmap <version>"). Atomic (temporary file + rename).
/// Throws IoError.
void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map);

/// The grids and the file metadata writeMapVdb writes, for callers that assemble map.vdb
/// from parts (a distributed run gathers each process's grids): the number of grids, grid i
/// (decoded on demand: 0 surface, 1 weight, then truncation once an integrator finalized the
/// map, then the extra grids), all of them, and the file metadata.
int mapVdbGridCount(const VoxelMap& map);
openvdb::GridBase::Ptr mapVdbGrid(const VoxelMap& map, int i);
openvdb::GridPtrVec mapVdbGrids(const VoxelMap& map);
openvdb::MetaMap mapVdbMetadata(const VoxelMap& map);
/// Writes `grids` and `meta` as a .vdb file, atomically. Throws IoError.
void writeVdbGrids(const std::filesystem::path& path, const openvdb::GridPtrVec& grids,
                   const openvdb::MetaMap& meta);
/// The same file with `count` grids made one at a time by `make(i)` and released once
/// written (only one grid in memory). Grid names must be unique and non-empty.
void writeVdbGridsOneByOne(const std::filesystem::path& path, int count,
                           const std::function<openvdb::GridBase::Ptr(int)>& make,
                           const openvdb::MetaMap& meta);

}  // namespace vdbmap
