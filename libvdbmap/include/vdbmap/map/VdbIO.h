// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"

#include <filesystem>
#include <functional>

namespace vdbmap {

class VoxelMap;

/// Writes map.vdb (docs/DATA.md): float grid "surface" (signed distance, m, level set class),
/// float grid "weight" (both decoded from the packed TSDF), the truncation grid (when the map
/// was finalized by an integrator: metadata "truncation_max_m"), every extra grid, and metadata (voxel size,
/// truncation settings, creator "vdbmap <version>"). Atomic (temporary file + rename).
/// Throws IoError.
void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map);

/// One part of the map as a map.vdb of its own (a tile's, tiling.map_vdb: per_tile): the
/// "surface" and "weight" grids and (when an integrator described the map: metadata
/// "truncation_max_m") the "truncation" grid of the leaves `keep` accepts (by origin), with
/// the map's metadata but "scans_integrated" and the entries of `meta` on top. The extra grids
/// are not written. Atomic. Returns the active voxels written. Throws IoError.
std::size_t writeMapVdbPart(const std::filesystem::path& path, const VoxelMap& map,
                            const std::function<bool(const openvdb::Coord&)>& keep,
                            const openvdb::MetaMap& meta);

/// The grids and the file metadata writeMapVdb writes, for callers that assemble map.vdb
/// from parts (a distributed run gathers each process's grids): the number of grids, grid i
/// (decoded on demand: 0 surface, 1 weight, then truncation once an integrator finalized the
/// map, then the extra grids) and the file metadata.
int mapVdbGridCount(const VoxelMap& map);
/// `keep` (if given): only the leaves it accepts, by origin, in the TSDF's grids (0 to 2).
openvdb::GridBase::Ptr mapVdbGrid(const VoxelMap& map, int i,
                                  const std::function<bool(const openvdb::Coord&)>& keep = nullptr);
openvdb::MetaMap mapVdbMetadata(const VoxelMap& map);
/// Writes a .vdb file (openvdb::io::File::write's file) of `count` grids made one at a time
/// by `make(i)` and released once written (only one grid in memory), atomically. Grid names
/// must be unique and non-empty. Throws IoError.
void writeVdbGridsOneByOne(const std::filesystem::path& path, int count,
                           const std::function<openvdb::GridBase::Ptr(int)>& make,
                           const openvdb::MetaMap& meta);

}  // namespace vdbmap
