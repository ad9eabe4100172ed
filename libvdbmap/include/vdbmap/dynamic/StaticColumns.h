// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// Thin static columns in an object (docs/dynamic.md, "Static columns"): a pole 0.2 m beside a
/// van's path is one object with the van while it passes. Of the object's points `members`
/// (indices into points_L, sensor frame L, z up), those `kept` by static evidence (per member:
/// a scan hit it and none saw through it), cut into parts connected through voxels of
/// `voxel_m` (26-neighbourhood) holding kept members; a part whose footprint (its L bounding
/// box in x and y) is at most `max_footprint_m` on both axes and whose height is at least
/// `min_height_m` is a column. Returns 1 per member of a column, else 0.
std::vector<std::uint8_t> staticColumns(const std::vector<Vec3f>& points_L, const std::vector<std::size_t>& members,
                                        const std::vector<std::uint8_t>& kept, float voxel_m,
                                        float max_footprint_m, float min_height_m);

}  // namespace vdbmap
