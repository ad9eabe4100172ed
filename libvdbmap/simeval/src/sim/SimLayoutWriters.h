// SPDX-License-Identifier: Apache-2.0
// The layout writers behind writeSimLayout: each moves the files of a sequence folder written
// by writeSimSequence (KITTI rig) into a dataset layout as downloaded (docs/DATA.md).
#pragma once

#include <filesystem>
#include <string>

#include "vdbmap/sim/SimLayout.h"

namespace vdbmap::sim {

/// Moves `from` to `to` (creating `to`'s parent), if `from` exists. Throws IoError.
void moveIfPresent(const std::filesystem::path& from, const std::filesystem::path& to);

/// The sequence's gt/, vignetting.txt and exposure.txt into `out_dir`/gt. Throws IoError.
void moveGroundTruth(const std::filesystem::path& sequence_dir,
                     const std::filesystem::path& out_dir);

/// A KITTI-360 drive under `out_dir` (SimLayoutKitti360.cpp): calibration/, data_3d_raw/,
/// data_2d_raw/, data_2d_semantics/, data_poses/ and gt/. Throws IoError.
void arrangeKitti360(const std::filesystem::path& sequence_dir, const SimLayoutOptions& layout,
                     const std::filesystem::path& out_dir);

}  // namespace vdbmap::sim
