// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdio>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/Kitti360.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap::test {

/// A tiny KITTI-360 root on disk (docs/DATA.md "KITTI-360"), drive
/// 2013_05_28_drive_0003_sync: scans of frames 0..3, IMU poses for frames 0, 1 and 3 only,
/// Velodyne timestamps, both perspective cameras (images for frames 0 and 3), and a calibration
/// in which no link is the identity: R_rect_00 and R_rect_01 rotate by ~1 degree, camera 1 is
/// rotated against camera 0, the IMU is rotated and offset.
struct Kitti360Fixture {
    static constexpr const char* kDrive = "2013_05_28_drive_0003_sync";
    Kitti360Calib calib;
    std::vector<Kitti360Pose> poses;
    std::filesystem::path root;

    static Isometry3d pose(double angle_rad, const Vec3d& axis, const Vec3d& t) {
        Isometry3d T = Isometry3d::Identity();
        T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
        T.translation() = t;
        return T;
    }

    static std::string frameName(int f) {
        char name[16];
        std::snprintf(name, sizeof(name), "%010d", f);
        return name;
    }

    explicit Kitti360Fixture(const std::filesystem::path& dir) : root(dir) {
        // Camera (z forward, x right, y down) in an IMU / Velodyne with x forward, z up.
        Isometry3d axes = Isometry3d::Identity();
        axes.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
        const Isometry3d T_IMU_C0 = pose(0.04, {0.3, 0.5, 1.0}, {1.52, 0.29, -0.13}) * axes;
        const Isometry3d T_C0_C1 = pose(0.02, {0.1, 1.0, 0.2}, {0.59, 0.005, -0.01});
        calib.T_IMU_C = {T_IMU_C0, T_IMU_C0 * T_C0_C1};
        calib.T_L_C0 = pose(0.01, {1.0, 0.2, 0.0}, {0.8, -0.3, 0.1}) * axes;  // camera 0 -> LiDAR
        calib.R_rect = {pose(0.018, {0.2, 1.0, 0.1}, Vec3d::Zero()).linear(),
                        pose(0.022, {1.0, -0.3, 0.2}, Vec3d::Zero()).linear()};
        Mat3d K;
        K << 552.55, 0, 682.05, 0, 552.55, 238.77, 0, 0, 1;
        Mat34d P0, P1;
        P0 << K, Vec3d::Zero();
        P1 << K, K * Vec3d(-0.59, 0, 0);
        calib.P_rect = {P0, P1};
        writeKitti360Calib(root / "calibration", calib, {{{96, 48}, {96, 48}}});

        for (const int f : {0, 1, 3}) {
            poses.push_back({f, pose(0.1 * f, {0.1, 0.2, 1.0},
                                     {1000.0 + 2.0 * f, 3000.0 - 0.5 * f, 115.0 + 0.1 * f})});
        }
        writeKitti360Poses(root / "data_poses" / kDrive / "poses.txt", poses);
        const auto velodyne = root / "data_3d_raw" / kDrive / "velodyne_points";
        std::vector<double> stamps;
        for (int f = 0; f < 4; ++f) {
            PointCloud scan;
            scan.points = {{10, 1, 0.5f}, {5, -2, -1.5f}};
            scan.intensity = {0.1f, 0.2f};
            writeBin(velodyne / "data" / (frameName(f) + ".bin"), scan);
            stamps.push_back(0.25 + 0.1 * f);
        }
        writeKitti360Timestamps(velodyne / "timestamps.txt", 1369730760, stamps);
        for (const char* camera : {"image_00", "image_01"}) {
            const auto images = root / "data_2d_raw" / kDrive / camera / "data_rect";
            for (const int f : {0, 3}) {
                writePng(images / (frameName(f) + ".png"),
                         cv::Mat(48, 96, CV_8UC3, cv::Scalar(10, 20, 30)));
            }
        }
    }
};

}  // namespace vdbmap::test
