// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/sim/SimRig.h"

namespace vdbmap {

/// The text of a generic-layout `dataset:` section for a simulated rig sequence: scans in
/// `scans_dir`, LiDAR poses in poses.txt (KITTI lines), and per rig camera its image_<name> /
/// semantic_<name> folders, inline intrinsics and T_C_L = T_V_C^-1 * T_V_L (17 significant
/// digits). Paths are relative to the sequence folder (`path: .`). A non-empty `labels_dir`
/// adds the key `labels_dir` (per-point LiDAR labels).
std::string rigDatasetYaml(const std::vector<RigCamera>& rig, const Isometry3d& T_V_L,
                           const std::string& scans_dir, const std::string& labels_dir = {});

/// Writes calib_<name>.txt (K:, D:, T: = T_C_L) per rig camera and dataset.yaml
/// (rigDatasetYaml) into the sequence folder `out_dir`, atomically. Throws IoError.
void writeRigCalibration(const std::filesystem::path& out_dir, const std::vector<RigCamera>& rig,
                         const Isometry3d& T_V_L, const std::string& scans_dir,
                         const std::string& labels_dir = {});

}  // namespace vdbmap
