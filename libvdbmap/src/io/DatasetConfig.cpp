// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/io/Dataset.h"

namespace vdbmap {

void DatasetConfig::declareOptions(OptionSpec& spec) {
    spec.add<std::string>("format",
                          "Layout: 'kitti' (KITTI odometry / SemanticKITTI sequence), 'kitti360' "
                          "(a KITTI-360 drive) or 'generic' (docs/DATA.md)",
                          format, "kitti");
    spec.add<std::string>("path",
                          "Sequence folder; kitti360: the KITTI-360 root (relative to the YAML "
                          "file)",
                          path, "");
    spec.add<std::string>("drive",
                          "kitti360: the drive, e.g. 2013_05_28_drive_0000_sync; empty = the "
                          "only one in data_3d_raw",
                          drive, "");
    spec.add("min_range_m", "Points closer to the sensor are dropped and counted", min_range_m, 1.0,
             "m");
    spec.add("max_range_m", "Points further from the sensor are dropped and counted", max_range_m,
             200.0, "m");
    spec.add("first_frame", "First frame to use (position in name order)", first_frame, 0);
    spec.add("num_frames", "Number of frames to use; -1 = all", num_frames, -1);
    spec.add("stride", "Use every n-th frame", stride, 1);
    spec.add<std::vector<std::string>>(
        "cameras",
        "KITTI: camera folders to use (image_2, image_3); kitti360: image_00, image_01; empty = "
        "all present. Generic: a list of camera maps (keys below)",
        cameras, {});
    spec.add<std::string>("scans_dir", "Generic: folder of .bin/.pcd/.ply scans, name order",
                          scans_dir, "scans");
    spec.add<std::string>("poses_file",
                          "Poses, relative to path. Generic: LiDAR poses T_W_L (empty = "
                          "poses.txt); KITTI: camera-0 poses T_W_C0 (empty = SEQ/poses.txt, else "
                          "the download's ../../poses/<SEQ>.txt); kitti360: frame + T_W_IMU "
                          "(empty = data_poses/<drive>/poses.txt)",
                          poses_file, "");
    spec.add<std::string>("pose_format", "Generic: 'kitti' (3x4 lines) or 'tum' (t x y z q)",
                          pose_format, "kitti");
    spec.add<std::string>("image_dir",
                          "Generic, one camera: its image folder; empty = none (or `cameras:`)",
                          image_dir, "");
    spec.add<std::string>("semantic_dir", "Generic: the camera's semantic id images", semantic_dir,
                          "");
    spec.add<std::vector<double>>("intrinsics", "Generic: fx fy cx cy", intrinsics, {}, "px");
    spec.add<std::vector<double>>("distortion", "Generic: OpenCV k1 k2 p1 p2 [k3]", distortion, {});
    spec.add<std::vector<double>>(
        "T_C_L", "Generic: LiDAR -> camera transform, 12 (3x4) or 16 row-major numbers", T_C_L, {},
        "m");
    spec.add<std::string>("calib_file",
                          "Generic: calibration file with K:, D:, T: lines (replaces intrinsics, "
                          "distortion, T_C_L)",
                          calib_file, "");
    spec.add<std::string>("labels_file",
                          "Label set 'id, name, r g b'; empty = docs/DATA.md default",
                          labels_file, "");
    spec.add<std::string>("labels_dir",
                          "Per-point LiDAR labels (SemanticKITTI .label, one per scan, same stem); "
                          "KITTI: default SEQ/labels when present; relative to path",
                          labels_dir, "");
}

}  // namespace vdbmap
