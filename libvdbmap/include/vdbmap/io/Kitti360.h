// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Camera.h"

namespace vdbmap {

/// The calibration of KITTI-360's Velodyne and its two perspective cameras (docs/DATA.md
/// "KITTI-360"), from the files of KITTI-360/calibration/. Frames: W the world of poses.txt,
/// IMU the GPS/IMU "pose" frame, Ck camera k (k = 0 left, 1 right) before rectification, Rk
/// its rectified frame, L the Velodyne.
struct Kitti360Calib {
    /// calib_cam_to_pose.txt "image_0k:": X_IMU = T_IMU_Ck X_Ck.
    std::array<std::optional<Isometry3d>, 2> T_IMU_C;
    /// calib_cam_to_velo.txt (12 numbers, no key): X_L = T_L_C0 X_C0.
    Isometry3d T_L_C0 = Isometry3d::Identity();
    /// perspective.txt "P_rect_0k:": the rectified projection; its left 3x3 is K_k.
    std::array<std::optional<Mat34d>, 2> P_rect;
    /// perspective.txt "R_rect_0k:": X_Rk = R_rect_k X_Ck.
    std::array<std::optional<Mat3d>, 2> R_rect;
};

/// Reads calib_cam_to_velo.txt, calib_cam_to_pose.txt (image_00 always, image_01 when camera 1
/// is in `cameras`) and, if `cameras` is not empty, perspective.txt (P_rect_0k and R_rect_0k of
/// each camera k in `cameras`, each 0 or 1) from `calibration_dir`. Other keys (calib_time,
/// S_00, K_00, image_02 ...) are not read. Throws IoError naming the file for a missing file,
/// the key for a missing key, and file:line for a malformed line or a transform that is not
/// rigid (R_rect included).
Kitti360Calib readKitti360Calib(const std::filesystem::path& calibration_dir,
                                const std::vector<int>& cameras);

/// Writes the three files of readKitti360Calib into `calibration_dir` (the cameras that are
/// set; perspective.txt with S_rect_0k = `image_size_px[k]`, width height), atomically. Throws
/// IoError.
void writeKitti360Calib(const std::filesystem::path& calibration_dir, const Kitti360Calib& calib,
                        const std::array<std::array<int, 2>, 2>& image_size_px);

/// The Velodyne's pose from the IMU's, the chain of docs/DATA.md:
///   T_W_L = T_W_IMU · T_IMU_C0 · T_C0_L,  T_C0_L = (T_L_C0)^-1.
/// Needs calib.T_IMU_C[0] (std::bad_optional_access otherwise).
Isometry3d kitti360LidarPose(const Isometry3d& T_W_IMU, const Kitti360Calib& calib);

/// Rectified perspective camera k (0 or 1) as a Camera whose frame is the rectified Rk, with
/// intrinsics K_k (the left 3x3 of P_rect_0k, width/height 0) and
///   T_C_L = T_Rk_L = R_rect_k · (T_IMU_Ck)^-1 · T_IMU_C0 · T_C0_L,
/// so that a Velodyne point projects as pixel ~ K_k · R_rect_k · X_Ck (the devkit's
/// projection; for camera 0 this is P_rect_00 · [R_rect_00 · X_C0; 1]). The 4th column of
/// P_rect_01 (the stereo baseline) is not used: camera 1 is placed by calib_cam_to_pose, as in
/// the KITTI-360 devkit. Throws InvalidInput naming `name` if the calibration of camera k is
/// missing or P_rect_0k is not K [I | t].
Camera kitti360Camera(const Kitti360Calib& calib, int k, const std::string& name);

/// One line of KITTI-360's data_poses/<drive>/poses.txt: a frame number and T_W_IMU.
struct Kitti360Pose {
    long long frame = 0;
    Isometry3d T_W_IMU = Isometry3d::Identity();
};

/// Reads poses.txt: lines "frame r11 r12 r13 tx r21 ... tz" (13 numbers, the first a
/// non-negative integer), frames strictly increasing. Blank lines are skipped. Throws IoError
/// naming file:line (wrong count, not a number, a frame that is not an integer or not
/// increasing, a rotation that is not one).
std::vector<Kitti360Pose> readKitti360Poses(const std::filesystem::path& path);

/// Writes poses.txt lines (full double precision), atomically. Throws IoError.
void writeKitti360Poses(const std::filesystem::path& path, const std::vector<Kitti360Pose>& poses);

/// Reads a KITTI-360 (and KITTI raw) timestamps.txt: one "YYYY-MM-DD HH:MM:SS.fffffffff" per
/// line (read as UTC), line i belonging to frame i. Returns the seconds since line 0's time,
/// from the whole seconds and the fractions apart, so that the nanosecond digits survive.
/// Throws IoError naming file:line for a malformed line.
std::vector<double> readKitti360Timestamps(const std::filesystem::path& path);

/// Writes timestamps.txt lines for `start_s` (whole seconds since 1970-01-01, UTC) plus
/// `seconds_since_start[i]`, with nanosecond digits, atomically. Throws IoError.
void writeKitti360Timestamps(const std::filesystem::path& path, std::int64_t start_s,
                             const std::vector<double>& seconds_since_start);

}  // namespace vdbmap
