// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// The mover's part of an object joined to a static one (docs/dynamic.md, "Joined objects"):
/// a van that stops beside a parked car is one object with it, larger than the van's track.
/// The static evidence splits them: of the object's points `members` (indices into points_L,
/// sensor frame L), those not `kept` (per member: a scan hit it and none saw through it) that
/// are connected to a `seed` member through voxels of `voxel_m` (26-neighbourhood) holding
/// points not kept. Returns 1 per member for those, else 0; a kept member is never reached.
/// Dynablox grows its clusters the same way, from its ever-free seeds over occupied voxels.
std::vector<std::uint8_t> moverOfJoined(const std::vector<Vec3f>& points_L, const std::vector<std::size_t>& members,
                                        const std::vector<std::uint8_t>& seed, const std::vector<std::uint8_t>& kept,
                                        float voxel_m);

}  // namespace vdbmap
