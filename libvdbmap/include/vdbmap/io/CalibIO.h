// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Camera.h"

namespace vdbmap {

/// Row-major 3x4 matrix, as in KITTI calib and pose files.
using Mat34d = Eigen::Matrix<double, 3, 4>;

/// KITTI odometry calib.txt (docs/DATA.md): projection matrices P0..P3 of the rectified cameras
/// (P_k = K_k [I | t_k], mapping camera-0 coordinates to pixels) and Tr, LiDAR -> camera 0.
struct KittiCalib {
    std::array<std::optional<Mat34d>, 4> P;  ///< P0..P3 (missing lines stay empty)
    Isometry3d Tr = Isometry3d::Identity();  ///< T_C0_L: X_C0 = Tr * X_L
};

/// Reads a KITTI calib.txt: lines "P0: 12 numbers" ... "P3:", and "Tr:" (or
/// "Tr_velo_to_cam:"). Other keys (R0_rect, Tr_imu_to_velo, ...) are ignored. Throws IoError
/// naming the file and line for a line without "key:", a wrong number count or a non-number,
/// and naming the file if there is no Tr line.
KittiCalib readKittiCalib(const std::filesystem::path& path);

/// Writes a KITTI calib.txt (P0..P3 that are set, then Tr), atomically. Throws IoError.
void writeKittiCalib(const std::filesystem::path& path, const KittiCalib& calib);

/// The pinhole intrinsics (width/height 0) of the left 3x3 block K of a rectified projection
/// matrix P = K [I | t]. Throws InvalidInput naming `what` unless K is upper triangular with
/// positive focal lengths, no skew and K(2,2) = 1.
CameraIntrinsics intrinsicsOfProjection(const Mat34d& P, const std::string& what);

/// Camera k of a KITTI sequence (docs/DATA.md): P_k = K_k [I | t_k], so t_k = K_k^-1 P_k[:,3],
/// T_Ck_C0 = [I | t_k] and T_Ck_L = T_Ck_C0 * Tr. Width/height are left 0 (read from the
/// images). Throws InvalidInput if the left 3x3 block of P_k is not an upper-triangular K with
/// positive focal lengths and no skew (intrinsicsOfProjection).
Camera kittiCamera(const Mat34d& P_k, const Isometry3d& Tr, const std::string& image_folder,
                   const std::string& semantic_folder = "");

/// A single camera's calibration file as in SensorsCalibration (lidar_camera_real):
/// "K: 9 numbers" (row-major 3x3), optional "D: k1 k2 p1 p2 [k3]", and "T: 12 numbers" (the
/// row-major 3x4 LiDAR -> camera transform T_C_L). Throws IoError naming the file and line.
struct CameraCalib {
    CameraIntrinsics intrinsics;  ///< width/height 0 (unknown)
    Isometry3d T_C_L = Isometry3d::Identity();
};

/// Reads a K / D / T calibration file. Throws IoError naming the file and line.
CameraCalib readCameraCalib(const std::filesystem::path& path);

/// Writes a K / D / T calibration file (K row-major 3x3, D k1 k2 p1 p2 k3, T the row-major 3x4
/// T_C_L; 17 significant digits, so readCameraCalib gives the same numbers), atomically.
/// Throws IoError.
void writeCameraCalib(const std::filesystem::path& path, const CameraCalib& calib);

/// Isometry from 12 (3x4) or 16 (4x4, last row 0 0 0 1) row-major numbers. Throws
/// InvalidInput naming `what` on another count or a bad last row.
Isometry3d isometryFromRowMajor(const std::vector<double>& values, const std::string& what);

}  // namespace vdbmap
