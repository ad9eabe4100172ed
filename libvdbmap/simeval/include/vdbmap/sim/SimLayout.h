// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/sim/SimSequence.h"

namespace vdbmap {

/// The folder layouts `vdbmap-sim --layout` writes: a simulated sequence as a public dataset is
/// downloaded (docs/DATA.md), so that the readers are tested on the layouts users have.
struct SimLayoutOptions {
    /// "sequence": our sequence folder (writeSimSequence, the default);
    /// "kitti-odometry": the KITTI odometry download, dataset/sequences/NN/{velodyne, image_2,
    ///   image_3, calib.txt, times.txt} and dataset/poses/NN.txt (no labels, no semantics);
    /// "semantic-kitti": SemanticKITTI, dataset/sequences/NN/{velodyne, labels, poses.txt,
    ///   calib.txt, times.txt} (no images);
    /// "kitti360": a KITTI-360 drive (data_3d_raw, data_2d_raw image_00|01, data_poses,
    ///   calibration, data_2d_semantics with KITTI-360 label ids), with a non-identity R_rect
    ///   per camera and a non-trivial IMU -> camera transform.
    /// Every layout keeps the ground truth in gt/ next to the dataset (kitti360: also the
    /// per-point LiDAR labels in gt/labels/).
    std::string layout = "sequence";
    /// The sequence number NN ("" = "00") or the KITTI-360 drive ("" =
    /// "2013_05_28_drive_0000_sync").
    std::string sequence;
    /// kitti360: frames left out of poses.txt (KITTI-360 has poses only for some frames).
    std::vector<std::size_t> unposed_frames{1};
};

/// The layout names, for the command line.
const std::vector<std::string>& simLayoutNames();

/// Where `dataset.path` points inside the output folder: "dataset/sequences/NN" for the two
/// KITTI layouts, "." for kitti360 and "sequence".
std::filesystem::path simLayoutDatasetPath(const SimLayoutOptions& layout);

/// Simulates `options` (writeSimSequence) and writes it into `out_dir` in `layout`. The layout
/// decides some options: kitti-odometry writes no LiDAR labels, semantic-kitti no images,
/// kitti360 both perspective cameras. Only the kitti rig (SimOptions::rig) has these layouts.
/// Throws ConfigError for a bad layout or option, IoError for write failures.
SimSummary writeSimLayout(SimOptions options, const SimLayoutOptions& layout,
                          const std::filesystem::path& out_dir);

/// The KITTI-360 / Cityscapes label id (kitti360Scripts labels.py `id`) of a class of our
/// default label set (docs/DATA.md): road 0 -> 7, ..., bicycle 18 -> 33, lane marking 19 ->
/// road 7, other object 20 -> unknown object 44, void 255 -> unlabeled 0.
std::uint8_t kitti360LabelId(std::uint8_t our_id);

}  // namespace vdbmap
