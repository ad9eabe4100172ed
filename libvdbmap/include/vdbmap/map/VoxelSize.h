// SPDX-License-Identifier: Apache-2.0
#pragma once

namespace vdbmap {

/// The smallest voxel edge a VoxelMap accepts, in metres. Below it OpenVDB's linear transform
/// refuses the scale (|det| = voxel^3 must exceed 3e-15, i.e. voxel > 1.4e-5 m) and the int32
/// index space would span only a few km; no LiDAR resolves surfaces finer than a millimetre,
/// so 1 mm is the documented floor (the integrate stage checks it as a config error).
inline constexpr double kMinVoxelSizeM = 1e-3;

/// The voxel edge of integrate.atsdf when voxel_size_m is not given, in metres: the paper's
/// streets. AtsdfConfig's lengths in voxels resolve against it there.
inline constexpr double kDefaultVoxelSizeM = 0.10;

}  // namespace vdbmap
