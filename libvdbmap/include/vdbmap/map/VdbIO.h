// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>

namespace vdbmap {

class VoxelMap;

/// Writes map.vdb (DATA.md): float grid "surface" (signed distance, m, level set class),
/// float grid "weight" (both decoded from the packed TSDF), the truncation grid (when the map
/// was finalized by an integrator: metadata "truncation_max_m"), every extra grid, and metadata (voxel size,
/// truncation settings, creator "vdbmap <version>"). Atomic (temporary file + rename).
/// Throws IoError.
void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map);

}  // namespace vdbmap
