// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Camera.h"
#include "vdbmap/io/DatasetCameraConfig.h"

namespace vdbmap {

class OptionSpec;
class LabelSet;

/// The `dataset:` section of a pipeline (docs/DATA.md). Declared through an OptionSpec so that the
/// YAML checks and `vdbmap describe dataset` work as for stages.
/// Relative `path` and `labels_file` resolve against the YAML file's folder; poses_file, the
/// generic layout's scans_dir, image_dir, semantic_dir and calib_file (also those of each
/// `cameras:` entry) against `path`.
///
/// Cameras of the generic layout: either one camera given by the top-level keys image_dir,
/// semantic_dir, intrinsics, distortion, T_C_L / calib_file, or a rig given by `cameras:` as a
/// list of maps (DatasetCameraConfig, bound into `rig`). In YAML the key `cameras` is a list of
/// folder names for the KITTI and KITTI-360 layouts and a list of maps for the generic layout.
struct DatasetConfig {
    /// "kitti" (KITTI odometry / SemanticKITTI sequence), "kitti360" (a KITTI-360 drive) or
    /// "generic"
    std::string format = "kitti";
    /// The sequence folder; for "kitti360" the KITTI-360 root (the folder holding calibration/,
    /// data_3d_raw/ ...). Relative paths: relative to the YAML file.
    std::string path;
    /// kitti360: the drive, e.g. "2013_05_28_drive_0000_sync" ("" = the only drive in
    /// data_3d_raw/).
    std::string drive;
    double min_range_m = 1.0;      ///< points closer to the sensor are dropped and counted
    double max_range_m = 200.0;    ///< points further away (absurd ranges) are dropped
    int first_frame = 0;
    int num_frames = -1;  ///< -1 = all
    int stride = 1;
    /// KITTI: camera folders to use (empty = image_2, image_3 if present); kitti360: image_00,
    /// image_01 (empty = those with a data_rect folder).
    std::vector<std::string> cameras;
    /// Generic: the cameras of a rig (YAML `cameras:` as a list of maps); empty = the single
    /// camera of the top-level keys below (or none). Setting both is a ConfigError.
    std::vector<DatasetCameraConfig> rig;
    // generic layout
    std::string scans_dir = "scans";  ///< .bin / .pcd / .ply files, sorted by name
    /// The poses, relative to `path`. Generic: LiDAR poses T_W_L ("" = poses.txt). KITTI:
    /// camera-0 poses T_W_C0 ("" = SEQ/poses.txt, else the odometry download's
    /// SEQ/../../poses/<SEQ>.txt). kitti360: IMU poses T_W_IMU with frame numbers ("" =
    /// data_poses/<drive>/poses.txt).
    std::string poses_file;
    std::string pose_format = "kitti";     ///< generic: "kitti" (3x4 lines) or "tum"
    std::string image_dir;                 ///< generic: the one camera's image folder ("" = none)
    std::string semantic_dir;              ///< generic: its semantic id images ("" = none)
    std::vector<double> intrinsics;        ///< generic: fx fy cx cy
    std::vector<double> distortion;        ///< generic: k1 k2 p1 p2 [k3]
    std::vector<double> T_C_L;             ///< generic: 12 (3x4) or 16 (4x4) row-major
    std::string calib_file;   ///< generic: K/D/T file; replaces intrinsics, distortion, T_C_L
    std::string labels_file;  ///< label set "id, name, r g b" ("" = docs/DATA.md default)
    /// Per-point LiDAR labels (SemanticKITTI .label, one per scan, same stem). Generic and
    /// kitti360: the folder ("" = none); KITTI: SEQ/labels/ when present (this key overrides
    /// the folder).
    std::string labels_dir;

    /// Declares every field (key = field name) with its doc, default and unit. `rig` is not a
    /// field of the spec: the YAML binder fills it from `cameras:` when that holds maps
    /// (loadDatasetSection, Pipeline), each map through DatasetCameraConfig::declareOptions.
    void declareOptions(OptionSpec& spec);
};

/// Counts from reading one scan.
struct ScanReadStats {
    std::size_t points_read = 0;
    std::size_t dropped_non_finite = 0;
    std::size_t dropped_range = 0;  ///< below min_range_m or above max_range_m
};

/// Drops points with a non-finite coordinate and points whose range |p| is outside
/// [min_range_m, max_range_m] (in the cloud's own sensor frame), keeping intensity aligned, and
/// adds the counts to `stats` (may be null). `points_read` counts the points before dropping.
void filterScan(PointCloud& cloud, double min_range_m, double max_range_m,
                ScanReadStats* stats = nullptr);
/// The same; `kept_index` (may be null) receives, for each kept point, its index in the cloud
/// as given (the point's index in its scan file).
void filterScan(PointCloud& cloud, double min_range_m, double max_range_m, ScanReadStats* stats,
                std::vector<std::uint32_t>* kept_index);

/// One frame of a sequence.
struct FrameInfo {
    std::size_t index = 0;  ///< position in the dataset (after first_frame / stride)
    std::string id;         ///< zero-padded file stem, "000042"
    Isometry3d T_W_L = Isometry3d::Identity();  ///< LiDAR pose in the world W
    std::filesystem::path scan_path;
    double timestamp_s = 0.0;
};

/// A sequence: frames with poses, cameras with calibration, and lazily read scans and images.
/// KITTI frames follow docs/DATA.md exactly: T_W_L = T_W_C0 * Tr, and camera k has
/// T_Ck_L = [I | t_k] * Tr with P_k = K_k [I | t_k]. KITTI-360 frames: T_W_L = T_W_IMU *
/// T_IMU_C0 * T_C0_L, and the rectified camera k has T_Rk_L = R_rect_k * T_IMU_Ck^-1 *
/// T_IMU_C0 * T_C0_L (Kitti360.h).
class Dataset {
public:
    /// Opens and validates the layout (folders, calib, poses vs. scans). Throws IoError naming
    /// the file and the problem (missing folder, malformed calib line, fewer poses than scans),
    /// ConfigError for bad options. Logs which poses file it read. Relative `config.path` is
    /// resolved against `base_dir`.
    static std::shared_ptr<Dataset> open(const DatasetConfig& config,
                                         const std::filesystem::path& base_dir = {});

    /// The configuration it was opened with (kitti360: `drive` set to the drive read).
    const DatasetConfig& config() const { return config_; }
    /// The sequence folder (absolute or as given, after resolution against base_dir).
    const std::filesystem::path& root() const { return root_; }
    /// Selected frames (after first_frame / num_frames / stride).
    std::size_t numFrames() const { return frames_.size(); }
    /// Frame i; throws std::out_of_range past numFrames().
    const FrameInfo& frame(std::size_t i) const { return frames_.at(i); }
    /// Cameras that have at least one image (cameras without images are dropped with a warning).
    const std::vector<Camera>& cameras() const { return cameras_; }
    /// The poses file that was read (the KITTI layout looks in two places).
    const std::filesystem::path& posesPath() const { return poses_path_; }
    /// Scans skipped because the poses file has no pose for them (KITTI-360 has poses only for
    /// some frames), before first_frame / num_frames / stride; 0 for the other layouts.
    std::size_t framesWithoutPose() const { return frames_without_pose_; }

    /// Reads the scan of frame i in the LiDAR frame, dropping non-finite points and points
    /// outside [min_range_m, max_range_m] (counted in `stats`). Throws IoError (truncated .bin,
    /// corrupt PCD header, ...).
    PointCloud loadScan(std::size_t i, ScanReadStats* stats = nullptr) const;
    /// Same into `cloud`, reusing its storage (a .bin scan is read without allocating).
    void loadScan(std::size_t i, PointCloud& cloud, ScanReadStats* stats = nullptr) const;
    /// The same; `kept_index` (may be null) gets each kept point's index in the scan file.
    void loadScan(std::size_t i, PointCloud& cloud, ScanReadStats* stats,
                  std::vector<std::uint32_t>* kept_index) const;

    /// Camera pose T_W_C = T_W_L * T_C_L^-1 of camera `cam` at frame i.
    Isometry3d T_W_C(std::size_t i, std::size_t cam) const;
    /// Colour image of camera `cam` at frame i, or nullopt if the file is missing.
    std::optional<std::filesystem::path> imagePath(std::size_t i, std::size_t cam) const;
    /// Semantic id image, or nullopt if missing / the camera has none.
    std::optional<std::filesystem::path> semanticPath(std::size_t i, std::size_t cam) const;

    /// Per-point LiDAR label file of frame i (`<labels_dir>/<frame id>.label`), or nullopt if
    /// the dataset has no label folder or the file is missing.
    std::optional<std::filesystem::path> lidarLabelPath(std::size_t i) const;
    /// The LiDAR label folder ("" = none).
    const std::filesystem::path& lidarLabelDir() const { return lidar_labels_dir_; }

    /// Number of (frame, camera) pairs of the selected frames without a colour image.
    std::size_t missingImages() const;
    /// Number of selected frames without a colour image of camera `cam` (out_of_range past
    /// cameras().size()).
    std::size_t missingImages(std::size_t cam) const;
    /// Number of (frame, camera) pairs without a semantic image, over cameras that have a
    /// semantic folder.
    std::size_t missingSemantics() const;
    /// The label set of `labels_file` (docs/DATA.md defaults if empty). Throws IoError.
    LabelSet labels() const;

private:
    Dataset() = default;
    friend class DatasetBuilder;

    DatasetConfig config_;
    std::filesystem::path root_;
    std::vector<FrameInfo> frames_;
    std::vector<Camera> cameras_;
    std::vector<std::filesystem::path> image_dirs_;     // per camera ("" = none)
    std::vector<std::filesystem::path> semantic_dirs_;  // per camera ("" = none)
    std::filesystem::path base_dir_;                    // folder of the YAML file
    std::filesystem::path lidar_labels_dir_;            // "" = no LiDAR labels
    std::filesystem::path poses_path_;                  // the poses file read
    std::size_t frames_without_pose_ = 0;               // scans skipped for lack of a pose
    // [frame][camera]: the file found for that view, empty if missing.
    std::vector<std::vector<std::filesystem::path>> image_paths_;
    std::vector<std::vector<std::filesystem::path>> semantic_paths_;
};

}  // namespace vdbmap
