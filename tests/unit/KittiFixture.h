// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/io/PoseIO.h"

namespace vdbmap::test {

/// A tiny KITTI sequence on disk with a non-identity Tr and a P2 with non-zero t (docs/DATA.md):
/// 3 frames, image_2 for frames 0 and 2 only, semantic_2 for frame 0 only, no image_3.
struct KittiFixture {
    Mat3d K;
    Vec3d t2;
    KittiCalib calib;
    std::vector<Isometry3d> T_W_C0;

    explicit KittiFixture(const std::filesystem::path& root) {
        K << 500, 0, 320, 0, 480, 240, 0, 0, 1;
        t2 = Vec3d(0.06, -0.01, 0.002);
        Mat34d P0, P2;
        P0 << K, Vec3d::Zero();
        P2 << K, K * t2;
        calib.P[0] = P0;
        calib.P[2] = P2;
        // LiDAR (x forward, y left, z up) -> camera 0 (z forward, x right, y down), slightly
        // tilted, with a lever arm: a KITTI-like, clearly non-identity Tr.
        Mat3d axes;
        axes << 0, -1, 0, 0, 0, -1, 1, 0, 0;
        calib.Tr = Isometry3d::Identity();
        calib.Tr.linear() = Eigen::AngleAxisd(0.05, Vec3d(1, 0, 0)).toRotationMatrix() * axes;
        calib.Tr.translation() = Vec3d(-0.01, -0.07, -0.27);
        for (int i = 0; i < 3; ++i) {
            Isometry3d T = Isometry3d::Identity();
            T.linear() = Eigen::AngleAxisd(0.1 * i, Vec3d(0, 1, 0)).toRotationMatrix();
            T.translation() = Vec3d(0.2 * i, 0.0, 1.5 * i);
            T_W_C0.push_back(T);
        }
        writeKittiCalib(root / "calib.txt", calib);
        writeKittiPoses(root / "poses.txt", T_W_C0);
        writeText(root / "times.txt", "0.0\n0.1\n0.2\n");
        const float nan = std::numeric_limits<float>::quiet_NaN();
        for (int i = 0; i < 3; ++i) {
            PointCloud scan;
            scan.points = {{10, 1, 0.5f}, {5, -2, -1.5f}, {nan, 0, 0}, {0.3f, 0.2f, 0}};
            scan.intensity = {0.1f, 0.2f, 0.3f, 0.4f};
            writeBin(root / "velodyne" / ("00000" + std::to_string(i) + ".bin"), scan);
        }
        const cv::Mat image(480, 640, CV_8UC3, cv::Scalar(10, 20, 30));
        writePng(root / "image_2" / "000000.png", image);
        writePng(root / "image_2" / "000002.png", image);
        writePng(root / "semantic_2" / "000000.png", cv::Mat(480, 640, CV_8UC1, cv::Scalar(13)));
    }
};

}  // namespace vdbmap::test
