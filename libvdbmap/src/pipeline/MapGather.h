// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace vdbmap {
class VoxelMap;
class TileGrid;
}  // namespace vdbmap

namespace vdbmap::detail {

/// This process's part of map.vdb in a distributed run: each grid writeMapVdb writes
/// (mapVdbGrid, decoded one at a time), keeping only the leaves of the tiles `owns(ix, iy)`
/// says are this process's (only there did it integrate every scan that reaches a voxel), as
/// one compressed OpenVDB stream per grid, packed into one string; the file metadata travels
/// with the first grid. `dropped_leaves` (if given) counts the surface leaves left out.
/// Throws Error for a grid that is not a float grid.
std::string mapPart(const VoxelMap& map, const TileGrid& grid,
                    const std::function<bool(int, int)>& owns, std::size_t* dropped_leaves);

/// Process 0's side: keeps every process's part (compressed), then writes map.vdb grid by
/// grid, each merged from the parts (their leaves are disjoint) and freed once written, so
/// that only one decoded grid is in memory.
class MapAssembler {
public:
    /// Adds one process's part (consumed). Throws IoError for bytes that are not a part or a
    /// part with another number of grids than the first.
    void add(std::string&& part);
    /// Writes the merged grids with the first part's metadata, atomically. Throws IoError.
    void write(const std::filesystem::path& path);
    /// Active voxels of the merged "surface" grid (after write()).
    std::size_t activeVoxels() const { return surface_voxels_; }
    bool empty() const { return parts_.empty(); }

private:
    std::vector<std::vector<std::string>> parts_;  ///< [part][grid]: one stream each
    std::size_t surface_voxels_ = 0;
};

}  // namespace vdbmap::detail
