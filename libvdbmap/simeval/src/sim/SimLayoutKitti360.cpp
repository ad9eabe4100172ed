// SPDX-License-Identifier: Apache-2.0
// A simulated KITTI-rig sequence as a KITTI-360 drive (docs/DATA.md "KITTI-360"). The rectified
// KITTI-360 cameras 00 and 01 are the simulator's cameras 2 and 3, so the rendered images move
// as they are; the calibration around them is made non-trivial (a rectifying rotation per
// camera, a rotated and offset IMU), so that a reader that drops a link of the frame chain
// projects the LiDAR away from where the images show it.
#include <cstdio>
#include <fstream>
#include <set>

#include "sim/SimLayoutWriters.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/Kitti360.h"
#include "vdbmap/io/PoseIO.h"

namespace vdbmap {
namespace {

namespace fs = std::filesystem;

/// 2013-05-28 08:46:00 UTC, the day of the first KITTI-360 drives: frame 0's timestamp.
constexpr std::int64_t kDriveStartS = 1369730760;

std::string drive360FrameName(std::size_t f) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%010zu", f);
    return buffer;
}

Isometry3d axisRotation(double angle_rad, const Vec3d& axis) {
    Isometry3d T = Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
    return T;
}

Isometry3d shift(const Vec3d& t) {
    Isometry3d T = Isometry3d::Identity();
    T.translation() = t;
    return T;
}

/// The simulated rig in KITTI-360's terms. Frames: C0s the simulator's KITTI camera 0 (the
/// frame of its poses.txt), Rk KITTI-360's rectified camera k = the simulator's camera 2 + k,
/// Ck KITTI-360's unrectified camera k (X_Rk = R_rect_k X_Ck), IMU the pose frame.
struct RigIn360 {
    Kitti360Calib calib;
    Isometry3d T_R0_C0s = Isometry3d::Identity();  ///< the simulator's [I | t_2]
};

RigIn360 rigIn360(const KittiCalib& sim) {
    const Mat3d K = sim.P[2]->leftCols<3>();
    const Vec3d t2 = K.inverse() * sim.P[2]->col(3);
    const Vec3d t3 = K.inverse() * sim.P[3]->col(3);
    RigIn360 rig;
    rig.T_R0_C0s = shift(t2);
    Kitti360Calib& c = rig.calib;
    const Isometry3d R_rect_00 = axisRotation(0.02, Vec3d(0.2, 1.0, 0.1));
    const Isometry3d R_rect_01 = axisRotation(0.015, Vec3d(1.0, -0.3, 0.2));
    c.R_rect = {R_rect_00.linear(), R_rect_01.linear()};
    // IMU: x forward, y left, z up; the camera looks along x, slightly rotated, 1.5 m ahead.
    Isometry3d axes = Isometry3d::Identity();
    axes.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    const Isometry3d T_IMU_C0 =
        shift(Vec3d(1.52, 0.29, -0.13)) * axes * axisRotation(0.03, Vec3d(0.3, 0.5, 1.0));
    // X_R1 = X_R0 + (t3 - t2): the simulator's stereo pair is rectified.
    const Isometry3d T_R0_R1 = shift(-(t3 - t2));
    c.T_IMU_C = {T_IMU_C0, T_IMU_C0 * R_rect_00.inverse() * T_R0_R1 * R_rect_01};
    // T_C0_L = T_C0_R0 · T_R0_C0s · Tr.
    c.T_L_C0 = (R_rect_00.inverse() * rig.T_R0_C0s * sim.Tr).inverse();
    Mat34d P0, P1;
    P0 << K, Vec3d::Zero();
    P1 << K, K * (t3 - t2);
    c.P_rect = {P0, P1};
    return rig;
}

/// The simulator's times.txt (seconds from frame 0, one per line).
std::vector<double> readSimTimes(const fs::path& path) {
    std::ifstream in(path);
    std::vector<double> times;
    double t = 0.0;
    while (in >> t) times.push_back(t);
    if (times.empty()) throw IoError("vdbmap-sim: no times in " + path.string());
    return times;
}

/// Moves each NNNNNN<ext> of `from` to `to`/NNNNNNNNNN<ext> (KITTI-360's 10-digit names).
void moveFrames(const fs::path& from, const fs::path& to, std::size_t frames,
                const std::string& ext) {
    for (std::size_t f = 0; f < frames; ++f) {
        char six[16];
        std::snprintf(six, sizeof(six), "%06zu", f);
        sim::moveIfPresent(from / (six + ext), to / (drive360FrameName(f) + ext));
    }
}

/// semantic_k/NNNNNN.png (our ids) -> `to`/NNNNNNNNNN.png in KITTI-360 label ids.
void writeSemantics(const fs::path& from, const fs::path& to, std::size_t frames) {
    std::error_code ec;
    if (!fs::is_directory(from, ec)) return;
    cv::Mat lut(1, 256, CV_8UC1);
    for (int id = 0; id < 256; ++id)
        lut.at<std::uint8_t>(id) = kitti360LabelId(static_cast<std::uint8_t>(id));
    for (std::size_t f = 0; f < frames; ++f) {
        char six[16];
        std::snprintf(six, sizeof(six), "%06zu", f);
        const fs::path source = from / (std::string(six) + ".png");
        if (!fs::exists(source, ec)) continue;
        cv::Mat ids;
        cv::LUT(readLabelImage(source), lut, ids);
        writePng(to / (drive360FrameName(f) + ".png"), ids);
    }
}

}  // namespace

std::uint8_t kitti360LabelId(std::uint8_t our_id) {
    // kitti360Scripts labels.py: the `id` of each trainId 0..18; lane marking has no class of
    // its own (road), other object is "unknown object".
    static constexpr std::uint8_t kIds[21] = {7,  8,  11, 12, 13, 17, 19, 20, 21, 22, 23,
                                              24, 25, 26, 27, 28, 31, 32, 33, 7,  44};
    return our_id < 21 ? kIds[our_id] : 0;
}

namespace sim {

void arrangeKitti360(const fs::path& sequence_dir, const SimLayoutOptions& layout,
                     const fs::path& out_dir) {
    const std::string drive =
        layout.sequence.empty() ? std::string("2013_05_28_drive_0000_sync") : layout.sequence;
    const KittiCalib sim_calib = readKittiCalib(sequence_dir / "calib.txt");
    const std::vector<Isometry3d> T_W_C0s = readKittiPoses(sequence_dir / "poses.txt");
    const RigIn360 rig = rigIn360(sim_calib);
    const std::size_t frames = T_W_C0s.size();

    // Calibration, and the IMU poses of the frames that keep one.
    std::array<std::array<int, 2>, 2> size_px{};
    for (int k = 0; k < 2; ++k) {
        const fs::path first = sequence_dir / ("image_" + std::to_string(2 + k)) / "000000.png";
        std::error_code ec;
        if (fs::exists(first, ec)) {
            const cv::Size size = readImageSize(first);
            size_px[k] = {size.width, size.height};
        }
    }
    writeKitti360Calib(out_dir / "calibration", rig.calib, size_px);
    const std::set<std::size_t> unposed(layout.unposed_frames.begin(), layout.unposed_frames.end());
    Isometry3d T_R0_C0 = Isometry3d::Identity();
    T_R0_C0.linear() = *rig.calib.R_rect[0];
    std::vector<Kitti360Pose> poses;
    for (std::size_t f = 0; f < frames; ++f) {
        if (unposed.count(f) != 0) continue;
        // T_W_IMU = T_W_R0 · T_R0_C0 · T_C0_IMU, T_W_R0 = T_W_C0s · T_C0s_R0.
        const Isometry3d T_W_R0 = T_W_C0s[f] * rig.T_R0_C0s.inverse();
        poses.push_back(
            {static_cast<long long>(f), T_W_R0 * T_R0_C0 * rig.calib.T_IMU_C[0]->inverse()});
    }
    writeKitti360Poses(out_dir / "data_poses" / drive / "poses.txt", poses);

    // Sensor data under their KITTI-360 names.
    const std::vector<double> stamps = readSimTimes(sequence_dir / "times.txt");
    const fs::path velodyne = out_dir / "data_3d_raw" / drive / "velodyne_points";
    moveFrames(sequence_dir / "velodyne", velodyne / "data", frames, ".bin");
    writeKitti360Timestamps(velodyne / "timestamps.txt", kDriveStartS, stamps);
    for (int k = 0; k < 2; ++k) {
        const fs::path images = sequence_dir / ("image_" + std::to_string(2 + k));
        std::error_code ec;
        if (!fs::is_directory(images, ec)) continue;
        const std::string camera = "image_0" + std::to_string(k);
        const fs::path camera_dir = out_dir / "data_2d_raw" / drive / camera;
        moveFrames(images, camera_dir / "data_rect", frames, ".png");
        writeKitti360Timestamps(camera_dir / "timestamps.txt", kDriveStartS, stamps);
        writeSemantics(sequence_dir / ("semantic_" + std::to_string(2 + k)),
                       out_dir / "data_2d_semantics" / "train" / drive / camera / "semantic",
                       frames);
    }
    moveGroundTruth(sequence_dir, out_dir);
    // KITTI-360 has no per-scan labels: the simulator's stay with its ground truth.
    moveFrames(sequence_dir / "labels", out_dir / "gt" / "labels", frames, ".label");
}

}  // namespace sim
}  // namespace vdbmap
