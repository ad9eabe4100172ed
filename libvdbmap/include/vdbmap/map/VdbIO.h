// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>

namespace vdbmap {

class VoxelMap;

/// Writes map.vdb (DATA.md): float grid "surface" (signed distance, m, level set class),
/// float grid "weight", the truncation grid, every extra grid, and metadata (voxel size,
/// truncation settings, creator "vdbmap <version>"). Atomic (temporary file + rename).
/// Throws IoError.
void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map);

}  // namespace vdbmap
