// SPDX-License-Identifier: Apache-2.0
// A KITTI-360 drive as downloaded (docs/DATA.md "KITTI-360"):
//   <root>/data_3d_raw/<drive>/velodyne_points/data/NNNNNNNNNN.bin  (+ timestamps.txt)
//   <root>/data_2d_raw/<drive>/image_00|01/data_rect/NNNNNNNNNN.png
//   <root>/data_poses/<drive>/poses.txt                             frame + T_W_IMU
//   <root>/calibration/calib_cam_to_pose.txt, calib_cam_to_velo.txt, perspective.txt
#include <algorithm>
#include <system_error>

#include "io/DatasetBuilder.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/Kitti360.h"

namespace vdbmap {
namespace {

namespace fs = std::filesystem;

/// The drive folder name: `drive`, or the only folder in data_3d_raw/.
std::string findDrive(const fs::path& root, const std::string& drive) {
    const fs::path raw = root / "data_3d_raw";
    DatasetBuilder::requireFolder(raw, "KITTI-360 data_3d_raw");
    if (!drive.empty()) return drive;
    std::vector<std::string> drives;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(raw, ec)) {
        if (entry.is_directory(ec)) drives.push_back(entry.path().filename().string());
    }
    std::sort(drives.begin(), drives.end());
    if (drives.size() == 1) return drives.front();
    if (drives.empty()) throw IoError("KITTI-360: no drive folder in " + raw.string());
    std::string list;
    for (const auto& d : drives) list += (list.empty() ? "" : ", ") + d;
    throw ConfigError("dataset: option 'drive' is empty but " + raw.string() + " holds " +
                      std::to_string(drives.size()) + " drives; set it to one of: " + list);
}

/// The perspective cameras to read (0 = image_00, 1 = image_01): the `cameras` option, or
/// those whose data_rect folder exists.
std::vector<int> selectCameras(const fs::path& images, const std::vector<std::string>& names) {
    std::vector<int> cameras;
    std::error_code ec;
    if (names.empty()) {
        for (int k = 0; k < 2; ++k) {
            const fs::path dir = images / ("image_0" + std::to_string(k)) / "data_rect";
            if (fs::is_directory(dir, ec)) cameras.push_back(k);
        }
        return cameras;
    }
    for (const std::string& name : names) {
        if (name != "image_00" && name != "image_01") {
            throw ConfigError("dataset: option 'cameras' entry '" + name +
                              "' is not a KITTI-360 perspective camera (image_00, image_01)");
        }
        const int k = name.back() - '0';
        DatasetBuilder::requireFolder(images / name / "data_rect", "KITTI-360 camera");
        if (std::find(cameras.begin(), cameras.end(), k) == cameras.end()) cameras.push_back(k);
    }
    return cameras;
}

/// Seconds since the drive's first Velodyne timestamp (line 0), per frame number; empty if
/// the drive has no timestamps.txt.
std::vector<double> readRelativeTimes(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return {};
    return readKitti360Timestamps(path);
}

/// The frames of the scans that have a pose; counts the others in `without_pose`.
std::vector<FrameInfo> posedFrames(const std::vector<fs::path>& scans,
                                   const std::vector<Kitti360Pose>& poses,
                                   const Kitti360Calib& calib, const std::vector<double>& times,
                                   const fs::path& times_path, std::size_t& without_pose) {
    std::vector<FrameInfo> frames;
    without_pose = 0;
    for (const fs::path& scan : scans) {
        FrameInfo frame;
        frame.id = scan.stem().string();
        frame.scan_path = scan;
        const long long number = DatasetBuilder::frameNumber(frame.id);
        if (number < 0) {
            throw IoError(scan.string() +
                          ": a KITTI-360 scan is named by its frame number (0000000042.bin)");
        }
        const auto pose =
            std::lower_bound(poses.begin(), poses.end(), number,
                             [](const Kitti360Pose& p, long long n) { return p.frame < n; });
        if (pose == poses.end() || pose->frame != number) {
            ++without_pose;  // KITTI-360 has poses only for some frames (not at standstill)
            continue;
        }
        frame.T_W_L = kitti360LidarPose(pose->T_W_IMU, calib);
        if (!times.empty()) {
            if (static_cast<std::size_t>(number) >= times.size()) {
                throw IoError(times_path.string() + " has " + std::to_string(times.size()) +
                              " timestamps but frame " + frame.id + " needs line " +
                              std::to_string(number + 1));
            }
            frame.timestamp_s = times[static_cast<std::size_t>(number)];
        }
        frames.push_back(std::move(frame));
    }
    return frames;
}

}  // namespace

void DatasetBuilder::openKitti360(Dataset& dataset) {
    const DatasetConfig config = dataset.config_;
    const fs::path& root = dataset.root_;
    if (!config.rig.empty()) {
        throw ConfigError(
            "dataset: the KITTI-360 layout takes 'cameras' as a list of folder names (image_00, "
            "image_01), got camera maps; camera maps are for format 'generic'");
    }
    const std::string drive = findDrive(root, config.drive);
    dataset.config_.drive = drive;  // config() tells which drive was read
    const fs::path velodyne = root / "data_3d_raw" / drive / "velodyne_points";
    const std::vector<fs::path> scans = listScans(velodyne / "data", "KITTI-360 velodyne");
    const fs::path poses_path = config.poses_file.empty()
                                    ? root / "data_poses" / drive / "poses.txt"
                                    : resolve(root, config.poses_file);
    std::error_code ec;
    if (!fs::is_regular_file(poses_path, ec)) {
        throw IoError("KITTI-360 poses not found: " + poses_path.string());
    }
    const std::vector<Kitti360Pose> poses = readKitti360Poses(poses_path);
    dataset.poses_path_ = poses_path;
    const fs::path images = root / "data_2d_raw" / drive;
    const std::vector<int> cameras = selectCameras(images, config.cameras);
    const Kitti360Calib calib = readKitti360Calib(root / "calibration", cameras);

    const fs::path times_path = velodyne / "timestamps.txt";
    std::vector<FrameInfo> all = posedFrames(scans, poses, calib, readRelativeTimes(times_path),
                                             times_path, dataset.frames_without_pose_);
    if (all.empty()) {
        throw IoError("KITTI-360: none of the " + std::to_string(scans.size()) + " scans in " +
                      (velodyne / "data").string() + " has a pose in " + poses_path.string() +
                      " (scans " + scans.front().stem().string() + " .. " +
                      scans.back().stem().string() + ", " + std::to_string(poses.size()) +
                      " poses)");
    }
    if (dataset.frames_without_pose_ > 0) {
        logInfo("dataset: " + std::to_string(dataset.frames_without_pose_) + " of " +
                std::to_string(scans.size()) + " KITTI-360 scans have no pose in " +
                poses_path.string() + " and are skipped");
    }
    selectFrames(dataset, std::move(all));

    for (const int k : cameras) {
        const std::string name = "image_0" + std::to_string(k);
        try {
            dataset.cameras_.push_back(kitti360Camera(calib, k, name));
        } catch (const InvalidInput& e) {
            throw IoError((root / "calibration" / "perspective.txt").string() + ": " + e.what());
        }
        dataset.image_dirs_.push_back(images / name / "data_rect");
        dataset.semantic_dirs_.emplace_back();
    }
}

}  // namespace vdbmap
