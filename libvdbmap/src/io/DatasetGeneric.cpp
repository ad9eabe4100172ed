// SPDX-License-Identifier: Apache-2.0
#include "io/DatasetBuilder.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/PoseIO.h"

namespace vdbmap {
namespace {

/// The single camera of the top-level keys, as a rig entry.
DatasetCameraConfig singleCamera(const DatasetConfig& config) {
    DatasetCameraConfig camera;
    camera.image_dir = config.image_dir;
    camera.semantic_dir = config.semantic_dir;
    camera.intrinsics = config.intrinsics;
    camera.distortion = config.distortion;
    camera.T_C_L = config.T_C_L;
    camera.calib_file = config.calib_file;
    return camera;
}

/// True if any top-level single-camera key is set.
bool hasSingleCameraKeys(const DatasetConfig& config) {
    return !config.image_dir.empty() || !config.semantic_dir.empty() ||
           !config.intrinsics.empty() || !config.distortion.empty() || !config.T_C_L.empty() ||
           !config.calib_file.empty();
}

/// `what` names the entry in messages: "dataset" for the top-level keys, "dataset: cameras[1]"
/// for a rig entry.
Camera genericCamera(const DatasetCameraConfig& config, const std::filesystem::path& root,
                     const std::string& what) {
    Camera camera;
    camera.name = config.name;
    if (camera.name.empty()) {
        camera.name = std::filesystem::path(config.image_dir).filename().string();
    }
    if (camera.name.empty()) camera.name = config.image_dir;
    camera.semantic_name = config.semantic_dir;
    if (!config.calib_file.empty()) {
        if (!config.intrinsics.empty() || !config.distortion.empty() || !config.T_C_L.empty()) {
            throw ConfigError(what +
                              ": set either 'calib_file' or 'intrinsics' / 'distortion' / "
                              "'T_C_L', not both");
        }
        const CameraCalib calib = readCameraCalib(DatasetBuilder::resolve(root, config.calib_file));
        camera.intrinsics = calib.intrinsics;
        camera.T_C_L = calib.T_C_L;
        return camera;
    }
    if (config.intrinsics.size() != 4 || !(config.intrinsics[0] > 0) ||
        !(config.intrinsics[1] > 0)) {
        throw ConfigError(what +
                          ": option 'intrinsics' must be [fx, fy, cx, cy] with positive "
                          "focal lengths (or set 'calib_file'), got " +
                          std::to_string(config.intrinsics.size()) + " values");
    }
    camera.intrinsics.fx = config.intrinsics[0];
    camera.intrinsics.fy = config.intrinsics[1];
    camera.intrinsics.cx = config.intrinsics[2];
    camera.intrinsics.cy = config.intrinsics[3];
    if (!config.distortion.empty() && config.distortion.size() != 4 &&
        config.distortion.size() != 5) {
        throw ConfigError(what +
                          ": option 'distortion' must be [k1, k2, p1, p2] or [k1, k2, p1, "
                          "p2, k3], got " +
                          std::to_string(config.distortion.size()) + " values");
    }
    for (std::size_t i = 0; i < config.distortion.size(); ++i) {
        camera.intrinsics.distortion[i] = config.distortion[i];
    }
    if (config.T_C_L.empty()) {
        throw ConfigError(what +
                          ": option 'T_C_L' (LiDAR -> camera, 12 or 16 row-major numbers) "
                          "is required with 'image_dir' (or set 'calib_file')");
    }
    try {
        camera.T_C_L = isometryFromRowMajor(config.T_C_L, what + ": option 'T_C_L'");
    } catch (const InvalidInput& e) {
        throw ConfigError(e.what());
    }
    return camera;
}

/// The cameras to open with the label used in their messages; checks that the layout's keys
/// are used consistently.
std::vector<std::pair<DatasetCameraConfig, std::string>> genericCameraEntries(
    const DatasetConfig& config) {
    std::vector<std::pair<DatasetCameraConfig, std::string>> entries;
    if (!config.cameras.empty()) {
        throw ConfigError(
            "dataset: the generic layout takes 'cameras' as a list of camera maps (keys "
            "name, image_dir, semantic_dir, intrinsics, distortion, T_C_L, calib_file), got "
            "folder name(s) such as '" +
            config.cameras.front() + "' (folder names are for the KITTI layout)");
    }
    if (!config.rig.empty()) {
        if (hasSingleCameraKeys(config)) {
            throw ConfigError(
                "dataset: set either the list 'cameras' or the single-camera keys image_dir, "
                "semantic_dir, intrinsics, distortion, T_C_L, calib_file, not both");
        }
        for (std::size_t c = 0; c < config.rig.size(); ++c) {
            entries.emplace_back(config.rig[c], "dataset: cameras[" + std::to_string(c) + "]");
        }
        return entries;
    }
    if (config.image_dir.empty()) {
        if (hasSingleCameraKeys(config)) {
            throw ConfigError(
                "dataset: camera keys (semantic_dir, intrinsics, distortion, T_C_L, calib_file) "
                "are set but 'image_dir' is empty");
        }
        return entries;
    }
    entries.emplace_back(singleCamera(config), "dataset");
    return entries;
}

}  // namespace

void DatasetBuilder::openGeneric(Dataset& dataset) {
    const DatasetConfig& config = dataset.config_;
    const std::filesystem::path& root = dataset.root_;
    const std::filesystem::path scans_dir = resolve(root, config.scans_dir);
    const std::vector<std::filesystem::path> scans = listScans(scans_dir, "scans");
    const std::filesystem::path poses_path =
        resolve(root, config.poses_file.empty() ? "poses.txt" : config.poses_file);
    dataset.poses_path_ = poses_path;
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

    for (const auto& [entry, what] : genericCameraEntries(config)) {
        if (entry.image_dir.empty()) {
            throw ConfigError(what + ": option 'image_dir' (the camera's image folder) is empty");
        }
        const std::filesystem::path image_dir = resolve(root, entry.image_dir);
        requireFolder(image_dir, what + ": camera image");
        std::filesystem::path semantic_dir;
        if (!entry.semantic_dir.empty()) {
            semantic_dir = resolve(root, entry.semantic_dir);
            requireFolder(semantic_dir, what + ": semantic image");
        }
        Camera camera = genericCamera(entry, root, what);
        for (const Camera& other : dataset.cameras_) {
            if (other.name == camera.name) {
                throw ConfigError(what + ": camera name '" + camera.name +
                                  "' is used twice (set 'name' to tell the cameras apart)");
            }
        }
        dataset.cameras_.push_back(std::move(camera));
        dataset.image_dirs_.push_back(image_dir);
        dataset.semantic_dirs_.push_back(semantic_dir);
    }
}

}  // namespace vdbmap
