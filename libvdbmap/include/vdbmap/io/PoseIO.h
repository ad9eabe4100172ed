// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// A pose with its time stamp (TUM lines).
struct StampedPose {
    double timestamp_s = 0.0;
    Isometry3d T_W_S = Isometry3d::Identity();  ///< sensor S in the world W
};

/// Reads KITTI poses: one line per frame, 12 numbers, the row-major 3x4 matrix [R | t] of
/// T_W_S. Blank lines are skipped. Throws IoError naming the file and line (wrong count, not
/// a number, non-finite value).
std::vector<Isometry3d> readKittiPoses(const std::filesystem::path& path);

/// Reads TUM poses: lines "t tx ty tz qx qy qz qw" ('#' comments). The quaternion is
/// normalised; a zero quaternion is an error. Throws IoError naming the file and line.
std::vector<StampedPose> readTumPoses(const std::filesystem::path& path);

/// Writes KITTI pose lines (full double precision), atomically. Throws IoError.
void writeKittiPoses(const std::filesystem::path& path, const std::vector<Isometry3d>& poses);
/// Writes TUM pose lines, atomically. Throws IoError.
void writeTumPoses(const std::filesystem::path& path, const std::vector<StampedPose>& poses);

}  // namespace vdbmap
