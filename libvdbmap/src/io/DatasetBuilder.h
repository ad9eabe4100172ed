// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/io/Dataset.h"

namespace vdbmap {

/// Fills a Dataset from one of the layouts of docs/DATA.md (friend of Dataset).
class DatasetBuilder {
public:
    /// KITTI odometry layout: velodyne/, calib.txt, poses.txt, times.txt, image_k/, semantic_k/.
    static void openKitti(Dataset& dataset);
    /// KITTI-360 drive: data_3d_raw/<drive>/velodyne_points, data_poses/<drive>/poses.txt,
    /// calibration/, data_2d_raw/<drive>/image_00|01/data_rect (DatasetKitti360.cpp).
    static void openKitti360(Dataset& dataset);
    /// Generic layout: scans_dir, poses_file (kitti | tum), and no camera, the one camera of the
    /// top-level keys, or the rig of `cameras:` (DatasetConfig::rig).
    static void openGeneric(Dataset& dataset);

    /// Sorted scan files of `folder` with a readable extension. Throws IoError if the folder
    /// is missing or holds no scans.
    static std::vector<std::filesystem::path> listScans(const std::filesystem::path& folder,
                                                        const std::string& what);
    /// Keeps the frames selected by first_frame / num_frames / stride and renumbers them.
    /// Throws ConfigError for out-of-range values.
    static void selectFrames(Dataset& dataset, std::vector<FrameInfo> all);
    /// Finds the image files of every (frame, camera), reads each camera's size from its first
    /// image, and drops cameras without images (logWarn).
    static void findImages(Dataset& dataset);
    /// The LiDAR label folder: `labels_dir` (must exist), else KITTI's SEQ/labels if present.
    static void findLidarLabels(Dataset& dataset);

    /// The frame number of a zero-padded file stem ("000042" -> 42), or -1 if it is not all
    /// digits (at most 12).
    static long long frameNumber(const std::string& stem);
    /// `relative` resolved against `base` (unchanged if absolute or base is empty).
    static std::filesystem::path resolve(const std::filesystem::path& base,
                                         const std::string& relative);
    /// Throws IoError "<what> folder not found: <path>" unless `folder` is a directory.
    static void requireFolder(const std::filesystem::path& folder, const std::string& what);
};

}  // namespace vdbmap
