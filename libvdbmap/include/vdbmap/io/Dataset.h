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
/// Relative `path` and `labels_file` resolve against the YAML file's folder; the generic
/// layout's scans_dir, poses_file, image_dir, semantic_dir and calib_file (also those of each
/// `cameras:` entry) against `path`.
///
/// Cameras of the generic layout: either one camera given by the top-level keys image_dir,
/// semantic_dir, intrinsics, distortion, T_C_L / calib_file, or a rig given by `cameras:` as a
/// list of maps (DatasetCameraConfig, bound into `rig`). In YAML the key `cameras` is a list of
/// folder names for the KITTI layout and a list of maps for the generic layout.
struct DatasetConfig {
    std::string format = "kitti";  ///< "kitti" (KITTI odometry layout) or "generic"
    std::string path;              ///< sequence folder (relative paths: relative to the YAML file)
    double min_range_m = 1.0;      ///< points closer to the sensor are dropped and counted
    double max_range_m = 200.0;    ///< points further away (absurd ranges) are dropped
    int first_frame = 0;
    int num_frames = -1;  ///< -1 = all
    int stride = 1;
    std::vector<std::string>
        cameras;  ///< KITTI: camera folders to use; empty = image_2, image_3 if present
    /// Generic: the cameras of a rig (YAML `cameras:` as a list of maps); empty = the single
    /// camera of the top-level keys below (or none). Setting both is a ConfigError.
    std::vector<DatasetCameraConfig> rig;
    // generic layout
    std::string scans_dir = "scans";       ///< .bin / .pcd / .ply files, sorted by name
    std::string poses_file = "poses.txt";  ///< sensor (LiDAR) poses T_W_L
    std::string pose_format = "kitti";     ///< "kitti" (3x4 lines) or "tum"
    std::string image_dir;                 ///< generic: the one camera's image folder ("" = none)
    std::string semantic_dir;              ///< generic: its semantic id images ("" = none)
    std::vector<double> intrinsics;        ///< generic: fx fy cx cy
    std::vector<double> distortion;        ///< generic: k1 k2 p1 p2 [k3]
    std::vector<double> T_C_L;             ///< generic: 12 (3x4) or 16 (4x4) row-major
    std::string calib_file;   ///< generic: K/D/T file; replaces intrinsics, distortion, T_C_L
    std::string labels_file;  ///< label set "id, name, r g b" ("" = docs/DATA.md default)
    /// Per-point LiDAR labels (SemanticKITTI .label, one per scan, same stem). Generic: the
    /// folder ("" = none); KITTI: SEQ/labels/ when present (this key overrides the folder).
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
/// T_Ck_L = [I | t_k] * Tr with P_k = K_k [I | t_k].
class Dataset {
public:
    /// Opens and validates the layout (folders, calib, poses vs. scans). Throws IoError naming
    /// the file and the problem (missing folder, malformed calib line, fewer poses than scans).
    /// Relative `config.path` is resolved against `base_dir`.
    static std::shared_ptr<Dataset> open(const DatasetConfig& config,
                                         const std::filesystem::path& base_dir = {});

    /// The configuration it was opened with.
    const DatasetConfig& config() const { return config_; }
    /// The sequence folder (absolute or as given, after resolution against base_dir).
    const std::filesystem::path& root() const { return root_; }
    /// Selected frames (after first_frame / num_frames / stride).
    std::size_t numFrames() const { return frames_.size(); }
    /// Frame i; throws std::out_of_range past numFrames().
    const FrameInfo& frame(std::size_t i) const { return frames_.at(i); }
    /// Cameras that have at least one image (cameras without images are dropped with a warning).
    const std::vector<Camera>& cameras() const { return cameras_; }

    /// Reads the scan of frame i in the LiDAR frame, dropping non-finite points and points
    /// outside [min_range_m, max_range_m] (counted in `stats`). Throws IoError (truncated .bin,
    /// corrupt PCD header, ...).
    PointCloud loadScan(std::size_t i, ScanReadStats* stats = nullptr) const;
    /// Same into `cloud`, reusing its storage (a .bin scan is read without allocating).
    void loadScan(std::size_t i, PointCloud& cloud, ScanReadStats* stats = nullptr) const;

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
    // [frame][camera]: the file found for that view, empty if missing.
    std::vector<std::vector<std::filesystem::path>> image_paths_;
    std::vector<std::vector<std::filesystem::path>> semantic_paths_;
};

}  // namespace vdbmap
