// SPDX-License-Identifier: Apache-2.0
// KITTI-360's calibration folder: calib_cam_to_velo.txt, calib_cam_to_pose.txt, perspective.txt
// (docs/DATA.md "KITTI-360"; the formats and frames of the KITTI-360 documentation and devkit).
#include <cstdio>

#include "io/CalibLines.h"
#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/Kitti360.h"

namespace vdbmap {
namespace {

namespace fs = std::filesystem;

std::string cameraKey(int k) { return "image_0" + std::to_string(k); }

/// The numbers of `key` in `lines`, `count` of them. Throws IoError naming the file and the key
/// (missing) or file:line (malformed). `why` says what needs the key.
const std::vector<double>& requireKey(const fs::path& path,
                                      const std::vector<detail::CalibLine>& lines,
                                      const std::string& key, std::size_t count,
                                      const std::string& why) {
    const detail::CalibLine* line = detail::findCalibLine(lines, key);
    if (line == nullptr) {
        throw IoError(path.string() + ": no '" + key + ":' line (" + why + ")");
    }
    detail::requireCount(path, *line, {count});
    return line->values;
}

/// A rigid transform from 12 row-major numbers; IoError naming `where` if it is not rigid.
Isometry3d rigid(const std::vector<double>& values, const std::string& where) {
    try {
        return isometryFromRowMajor(values, where);
    } catch (const InvalidInput& e) {
        throw IoError(e.what());
    }
}

/// calib_cam_to_velo.txt: 12 numbers without a key, on one line (or spread over lines).
Isometry3d readCamToVelo(const fs::path& path) {
    std::vector<double> values;
    std::vector<double> line_values;
    std::size_t last_line = 0;
    detail::forEachLine(path, [&](const detail::TextLine& line) {
        if (line.tokens.empty() || line.tokens.front().front() == '#') return;
        if (!detail::parseDoubles(line.tokens, 0, line_values)) {
            throw IoError(detail::lineMessage(path, line,
                                              "expected numbers (the 3x4 camera-0 -> "
                                              "Velodyne transform)"));
        }
        values.insert(values.end(), line_values.begin(), line_values.end());
        last_line = line.number;
    });
    if (values.size() != 12) {
        throw IoError(path.string() + ": expected 12 numbers (row-major 3x4 T_L_C0, camera 0 -> " +
                      "Velodyne), got " + std::to_string(values.size()));
    }
    return rigid(values, detail::fileLine(path, last_line));
}

/// requireKey's values as a rigid transform, errors naming file:line.
Isometry3d rigidKey(const fs::path& path, const std::vector<detail::CalibLine>& lines,
                    const std::string& key, const std::string& why) {
    const std::vector<double>& values = requireKey(path, lines, key, 12, why);
    return rigid(values, detail::fileLine(path, detail::findCalibLine(lines, key)->line_number) +
                             ": '" + key + "'");
}

/// R_rect_0k: a rotation; IoError naming file:line otherwise.
Mat3d rotationKey(const fs::path& path, const std::vector<detail::CalibLine>& lines,
                  const std::string& key, const std::string& why) {
    const std::vector<double>& v = requireKey(path, lines, key, 9, why);
    const std::vector<double> as_transform{v[0], v[1], v[2], 0,    v[3], v[4],
                                           v[5], 0,    v[6], v[7], v[8], 0};
    const std::string where =
        detail::fileLine(path, detail::findCalibLine(lines, key)->line_number) + ": '" + key + "'";
    return rigid(as_transform, where).linear();
}

std::string joinNumbers(const double* values, std::size_t count) {
    std::string text;
    char buffer[40];
    for (std::size_t i = 0; i < count; ++i) {
        std::snprintf(buffer, sizeof(buffer), "%s%.17g", i == 0 ? "" : " ", values[i]);
        text += buffer;
    }
    return text;
}

std::string row34(const Eigen::Matrix<double, 3, 4>& m) {
    const Eigen::Matrix<double, 3, 4, Eigen::RowMajor> r = m;
    return joinNumbers(r.data(), 12);
}

}  // namespace

Kitti360Calib readKitti360Calib(const fs::path& calibration_dir, const std::vector<int>& cameras) {
    Kitti360Calib calib;
    calib.T_L_C0 = readCamToVelo(calibration_dir / "calib_cam_to_velo.txt");

    const fs::path to_pose = calibration_dir / "calib_cam_to_pose.txt";
    const auto pose_lines = detail::readCalibLines(to_pose, detail::CalibText::Lenient);
    calib.T_IMU_C[0] = rigidKey(to_pose, pose_lines, cameraKey(0),
                                "camera 0 -> IMU, needed for "
                                "the Velodyne's pose");
    if (cameras.empty()) return calib;

    const fs::path perspective = calibration_dir / "perspective.txt";
    const auto lines = detail::readCalibLines(perspective, detail::CalibText::Lenient);
    for (const int k : cameras) {
        if (k != 0 && k != 1) {
            throw InvalidInput("readKitti360Calib: perspective camera " + std::to_string(k) +
                               " (valid: 0, 1)");
        }
        const std::string why = "camera " + cameraKey(k);
        calib.T_IMU_C[k] = rigidKey(to_pose, pose_lines, cameraKey(k), why);
        const std::string p_key = "P_rect_0" + std::to_string(k);
        calib.P_rect[k] = detail::toMat34(requireKey(perspective, lines, p_key, 12, why));
        calib.R_rect[k] = rotationKey(perspective, lines, "R_rect_0" + std::to_string(k), why);
    }
    return calib;
}

void writeKitti360Calib(const fs::path& calibration_dir, const Kitti360Calib& calib,
                        const std::array<std::array<int, 2>, 2>& image_size_px) {
    const Eigen::Matrix<double, 3, 4> T_L_C0 = calib.T_L_C0.matrix().topRows<3>();
    writeFileAtomically(calibration_dir / "calib_cam_to_velo.txt", row34(T_L_C0) + "\n");
    std::string to_pose;
    for (int k = 0; k < 2; ++k) {
        if (!calib.T_IMU_C[k]) continue;
        to_pose += cameraKey(k) + ": " + row34(calib.T_IMU_C[k]->matrix().topRows<3>()) + "\n";
    }
    writeFileAtomically(calibration_dir / "calib_cam_to_pose.txt", to_pose);
    // The KITTI raw calib_cam_to_cam.txt layout, as KITTI-360 ships it; only the rectified
    // keys carry our numbers (the raw K_0k / D_0k are not written).
    std::string perspective = "calib_time: 09-Jan-2012 14:00:15\n";
    for (int k = 0; k < 2; ++k) {
        if (!calib.P_rect[k] || !calib.R_rect[k]) continue;
        const std::string kk = "0" + std::to_string(k);
        const double size[2] = {static_cast<double>(image_size_px[k][0]),
                                static_cast<double>(image_size_px[k][1])};
        const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R = *calib.R_rect[k];
        perspective += "S_rect_" + kk + ": " + joinNumbers(size, 2) + "\n";
        perspective += "R_rect_" + kk + ": " + joinNumbers(R.data(), 9) + "\n";
        perspective += "P_rect_" + kk + ": " + row34(*calib.P_rect[k]) + "\n";
    }
    writeFileAtomically(calibration_dir / "perspective.txt", perspective);
}

Isometry3d kitti360LidarPose(const Isometry3d& T_W_IMU, const Kitti360Calib& calib) {
    // docs/DATA.md: T_W_L = T_W_IMU · T_IMU_C0 · T_C0_L, T_C0_L = (T_L_C0)^-1.
    return T_W_IMU * calib.T_IMU_C[0].value() * calib.T_L_C0.inverse();
}

Camera kitti360Camera(const Kitti360Calib& calib, int k, const std::string& name) {
    if ((k != 0 && k != 1) || !calib.T_IMU_C[0] || !calib.T_IMU_C[k] || !calib.P_rect[k] ||
        !calib.R_rect[k]) {
        throw InvalidInput("camera " + name + ": no KITTI-360 calibration for perspective camera " +
                           std::to_string(k));
    }
    Camera camera;
    camera.name = name;
    camera.intrinsics = intrinsicsOfProjection(*calib.P_rect[k], "camera " + name + ": P_rect");
    // docs/DATA.md: T_Rk_L = R_rect_k · (T_IMU_Ck)^-1 · T_IMU_C0 · T_C0_L, the devkit's
    // TrVeloToRect; the pixel is K_k · X_Rk.
    Isometry3d T_Rk_Ck = Isometry3d::Identity();
    T_Rk_Ck.linear() = *calib.R_rect[k];
    const Isometry3d T_Ck_C0 = calib.T_IMU_C[k]->inverse() * *calib.T_IMU_C[0];
    camera.T_C_L = T_Rk_Ck * T_Ck_C0 * calib.T_L_C0.inverse();
    return camera;
}

}  // namespace vdbmap
