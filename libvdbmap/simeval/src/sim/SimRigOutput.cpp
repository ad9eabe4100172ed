// SPDX-License-Identifier: Apache-2.0
#include "sim/SimRigOutput.h"

#include <cstdio>

#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/CalibIO.h"

namespace vdbmap {
namespace {

std::string numberList(const std::vector<double>& values) {
    std::string out = "[";
    char buffer[40];
    for (std::size_t i = 0; i < values.size(); ++i) {
        std::snprintf(buffer, sizeof(buffer), "%s%.17g", i == 0 ? "" : ", ", values[i]);
        out += buffer;
    }
    return out + "]";
}

Isometry3d cameraFromLidar(const RigCamera& camera, const Isometry3d& T_V_L) {
    return camera.T_V_C.inverse() * T_V_L;
}

}  // namespace

std::string rigDatasetYaml(const std::vector<RigCamera>& rig, const Isometry3d& T_V_L,
                           const std::string& scans_dir, const std::string& labels_dir) {
    std::string text =
        "# SPDX-License-Identifier: Apache-2.0\n"
        "# Written by vdbmap-sim: the dataset section of this generic-layout sequence\n"
        "# (docs/DATA.md of vdbmap). Use it as is (`vdbmap eval --dataset` reads it; relative\n"
        "# paths are relative to this file), or copy it into a pipeline and point `path` at\n"
        "# this folder.\n"
        "dataset:\n"
        "  format: generic\n"
        "  path: .\n"
        "  scans_dir: " +
        scans_dir +
        "\n"
        "  poses_file: poses.txt      # LiDAR poses T_W_L, KITTI 3x4 lines\n"
        "  pose_format: kitti\n";
    if (!labels_dir.empty()) {
        text += "  labels_dir: " + labels_dir +
                "      # per-point LiDAR labels (.label; SemanticKITTI ids unless written with "
                "--lidar-label-ids ours)\n";
    }
    text += "  cameras:\n";
    for (const RigCamera& camera : rig) {
        const CameraIntrinsics& K = camera.intrinsics;
        const Eigen::Matrix4d T = cameraFromLidar(camera, T_V_L).matrix();
        std::vector<double> T_C_L;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) T_C_L.push_back(T(r, c));
        }
        text += "    - name: " + camera.name + "\n";
        text += "      image_dir: image_" + camera.name + "\n";
        text += "      semantic_dir: semantic_" + camera.name + "\n";
        text += "      intrinsics: " + numberList({K.fx, K.fy, K.cx, K.cy}) + "  # fx fy cx cy, " +
                std::to_string(K.width) + "x" + std::to_string(K.height) + " px\n";
        text += "      T_C_L: " + numberList(T_C_L) + "\n";
    }
    return text;
}

void writeRigCalibration(const std::filesystem::path& out_dir, const std::vector<RigCamera>& rig,
                         const Isometry3d& T_V_L, const std::string& scans_dir,
                         const std::string& labels_dir) {
    for (const RigCamera& camera : rig) {
        CameraCalib calib;
        calib.intrinsics = camera.intrinsics;
        calib.T_C_L = cameraFromLidar(camera, T_V_L);
        writeCameraCalib(out_dir / ("calib_" + camera.name + ".txt"), calib);
    }
    writeFileAtomically(out_dir / "dataset.yaml", rigDatasetYaml(rig, T_V_L, scans_dir, labels_dir));
}

}  // namespace vdbmap
