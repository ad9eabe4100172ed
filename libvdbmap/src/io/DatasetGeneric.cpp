// SPDX-License-Identifier: Apache-2.0
#include "io/DatasetBuilder.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/PoseIO.h"

namespace vdbmap {
namespace {

Camera genericCamera(const DatasetConfig& config, const std::filesystem::path& root) {
    Camera camera;
    camera.name = std::filesystem::path(config.image_dir).filename().string();
    if (camera.name.empty()) camera.name = config.image_dir;
    camera.semantic_name = config.semantic_dir;
    if (!config.calib_file.empty()) {
        const CameraCalib calib = readCameraCalib(DatasetBuilder::resolve(root, config.calib_file));
        camera.intrinsics = calib.intrinsics;
        camera.T_C_L = calib.T_C_L;
        return camera;
    }
    if (config.intrinsics.size() != 4 || !(config.intrinsics[0] > 0) ||
        !(config.intrinsics[1] > 0)) {
        throw ConfigError(
            "dataset: option 'intrinsics' must be [fx, fy, cx, cy] with positive "
            "focal lengths (or set 'calib_file'), got " +
            std::to_string(config.intrinsics.size()) + " values");
    }
    camera.intrinsics.fx = config.intrinsics[0];
    camera.intrinsics.fy = config.intrinsics[1];
    camera.intrinsics.cx = config.intrinsics[2];
    camera.intrinsics.cy = config.intrinsics[3];
    if (!config.distortion.empty() && config.distortion.size() != 4 &&
        config.distortion.size() != 5) {
        throw ConfigError(
            "dataset: option 'distortion' must be [k1, k2, p1, p2] or [k1, k2, p1, "
            "p2, k3], got " +
            std::to_string(config.distortion.size()) + " values");
    }
    for (std::size_t i = 0; i < config.distortion.size(); ++i) {
        camera.intrinsics.distortion[i] = config.distortion[i];
    }
    if (config.T_C_L.empty()) {
        throw ConfigError(
            "dataset: option 'T_C_L' (LiDAR -> camera, 12 or 16 row-major numbers) "
            "is required with 'image_dir' (or set 'calib_file')");
    }
    try {
        camera.T_C_L = isometryFromRowMajor(config.T_C_L, "dataset: option 'T_C_L'");
    } catch (const InvalidInput& e) {
        throw ConfigError(e.what());
    }
    return camera;
}

}  // namespace

void DatasetBuilder::openGeneric(Dataset& dataset) {
    const DatasetConfig& config = dataset.config_;
    const std::filesystem::path& root = dataset.root_;
    const std::filesystem::path scans_dir = resolve(root, config.scans_dir);
    const std::vector<std::filesystem::path> scans = listScans(scans_dir, "scans");
    const std::filesystem::path poses_path = resolve(root, config.poses_file);
    std::vector<StampedPose> poses;
    if (config.pose_format == "kitti") {
        for (const Isometry3d& T : readKittiPoses(poses_path)) poses.push_back({0.0, T});
    } else if (config.pose_format == "tum") {
        poses = readTumPoses(poses_path);
    } else {
        throw ConfigError("dataset: option 'pose_format' must be 'kitti' or 'tum', got '" +
                          config.pose_format + "'");
    }
    if (poses.size() < scans.size()) {
        throw IoError("fewer poses than scans: " + poses_path.string() + " has " +
                      std::to_string(poses.size()) + " poses but " + scans_dir.string() + " has " +
                      std::to_string(scans.size()) + " scans");
    }
    // Generic poses are the sensor's own: line i is T_W_L of the i-th scan in name order.
    std::vector<FrameInfo> all;
    for (std::size_t k = 0; k < scans.size(); ++k) {
        FrameInfo frame;
        frame.id = scans[k].stem().string();
        frame.scan_path = scans[k];
        frame.T_W_L = poses[k].T_W_S;
        frame.timestamp_s = poses[k].timestamp_s;
        all.push_back(std::move(frame));
    }
    selectFrames(dataset, std::move(all));

    if (config.image_dir.empty()) return;
    const std::filesystem::path image_dir = resolve(root, config.image_dir);
    requireFolder(image_dir, "camera image");
    std::filesystem::path semantic_dir;
    if (!config.semantic_dir.empty()) {
        semantic_dir = resolve(root, config.semantic_dir);
        requireFolder(semantic_dir, "semantic image");
    }
    dataset.cameras_.push_back(genericCamera(config, root));
    dataset.image_dirs_.push_back(image_dir);
    dataset.semantic_dirs_.push_back(semantic_dir);
}

}  // namespace vdbmap
