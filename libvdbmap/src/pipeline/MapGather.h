// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

namespace vdbmap {
class VoxelMap;
class TileGrid;
}  // namespace vdbmap

namespace vdbmap::detail {

/// This process's part of map.vdb in a distributed run: the grids writeMapVdb writes
/// (mapVdbGrids), keeping only the leaves of the tiles `owns(ix, iy)` says are this
/// process's (only there did it integrate every scan that reaches a voxel), with the file
/// metadata, as an OpenVDB stream. `dropped_leaves` (if given) counts the leaves left out.
/// Throws Error for a grid that is not a float grid.
std::string mapPart(const VoxelMap& map, const TileGrid& grid,
                    const std::function<bool(int, int)>& owns, std::size_t* dropped_leaves);

/// Merges the parts of all processes (their leaves are disjoint) and writes map.vdb.
class MapAssembler {
public:
    /// Adds one process's part (consumed). Throws IoError for bytes that are not a part.
    void add(std::string&& part);
    /// Writes the merged grids with the first part's metadata, atomically. Throws IoError.
    void write(const std::filesystem::path& path) const;
    /// Active voxels of the merged "surface" grid.
    std::size_t activeVoxels() const;
    bool empty() const { return grids_.empty(); }

private:
    openvdb::GridPtrVec grids_;
    openvdb::MetaMap::Ptr meta_;
};

}  // namespace vdbmap::detail
