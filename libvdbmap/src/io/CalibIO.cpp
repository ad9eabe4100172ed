// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/CalibIO.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "io/CalibLines.h"
#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {
namespace detail {

std::vector<CalibLine> readCalibLines(const std::filesystem::path& path, CalibText mode) {
    const std::string text = readWholeFile(path);
    std::istringstream lines(text);
    std::string line;
    std::size_t line_number = 0;
    std::vector<CalibLine> result;
    while (std::getline(lines, line)) {
        ++line_number;
        const std::string_view content = trim(line);
        if (content.empty() || content.front() == '#') continue;
        const std::size_t colon = content.find(':');
        CalibLine entry;
        entry.line_number = line_number;
        entry.text = std::string(content.substr(0, 160));
        if (colon == std::string_view::npos || colon == 0) {
            throw IoError(fileLine(path, line_number) +
                          ": malformed calibration line (expected 'KEY: numbers'): '" + entry.text +
                          "'");
        }
        entry.key = std::string(trim(content.substr(0, colon)));
        if (!parseDoubles(splitWhitespace(content.substr(colon + 1)), 0, entry.values)) {
            if (mode == CalibText::Strict) {
                throw IoError(fileLine(path, line_number) + ": calibration '" + entry.key +
                              "' has a value that is not a number: '" + entry.text + "'");
            }
            entry.numeric = false;
            entry.values.clear();
        }
        for (const double v : entry.values) {
            if (!std::isfinite(v)) {
                throw IoError(fileLine(path, line_number) + ": calibration '" + entry.key +
                              "' has a non-finite value");
            }
        }
        result.push_back(std::move(entry));
    }
    return result;
}

const CalibLine* findCalibLine(const std::vector<CalibLine>& lines, const std::string& key) {
    for (const CalibLine& line : lines) {
        if (line.key == key) return &line;
    }
    return nullptr;
}

Mat34d toMat34(const std::vector<double>& v) {
    Mat34d m;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) m(r, c) = v[r * 4 + c];
    }
    return m;
}

void requireCount(const std::filesystem::path& path, const CalibLine& line,
                  std::initializer_list<std::size_t> counts) {
    if (!line.numeric) {
        throw IoError(fileLine(path, line.line_number) + ": calibration '" + line.key +
                      "' has a value that is not a number: '" + line.text + "'");
    }
    for (const std::size_t c : counts) {
        if (line.values.size() == c) return;
    }
    std::string expected;
    for (const std::size_t c : counts)
        expected += (expected.empty() ? "" : " or ") + std::to_string(c);
    throw IoError(fileLine(path, line.line_number) + ": calibration '" + line.key + "' needs " +
                  expected + " numbers, got " + std::to_string(line.values.size()));
}

}  // namespace detail

using detail::CalibLine;
using detail::readCalibLines;
using detail::requireCount;
using detail::toMat34;

Isometry3d isometryFromRowMajor(const std::vector<double>& values, const std::string& what) {
    if (values.size() != 12 && values.size() != 16) {
        throw InvalidInput(what +
                           ": a transform needs 12 (3x4) or 16 (4x4) row-major numbers, got " +
                           std::to_string(values.size()));
    }
    if (values.size() == 16 && (std::abs(values[12]) > 1e-9 || std::abs(values[13]) > 1e-9 ||
                                std::abs(values[14]) > 1e-9 || std::abs(values[15] - 1) > 1e-9)) {
        throw InvalidInput(what + ": the last row of a 4x4 transform must be 0 0 0 1");
    }
    Isometry3d T = Isometry3d::Identity();
    T.matrix().topRows<3>() = toMat34(values);
    // Rigid transforms only: a scaled or sheared 3x3 is well-formed text but wrong data.
    const Mat3d R = T.linear();
    const double orthogonality = (R.transpose() * R - Mat3d::Identity()).cwiseAbs().maxCoeff();
    if (!T.matrix().allFinite() || !(orthogonality < 1e-3) || !(R.determinant() > 0)) {
        throw InvalidInput(what + ": the transform's left 3x3 is not a rotation (|R^T R - I| = " +
                           std::to_string(orthogonality) + ", det = " +
                           std::to_string(R.determinant()) + ")");
    }
    return T;
}

KittiCalib readKittiCalib(const std::filesystem::path& path) {
    KittiCalib calib;
    bool have_tr = false;
    for (const CalibLine& line : readCalibLines(path)) {
        if (line.key == "P0" || line.key == "P1" || line.key == "P2" || line.key == "P3") {
            requireCount(path, line, {12});
            calib.P[line.key[1] - '0'] = toMat34(line.values);
        } else if (line.key == "Tr" || line.key == "Tr_velo_to_cam") {
            requireCount(path, line, {12});
            calib.Tr = isometryFromRowMajor(line.values, path.string());
            have_tr = true;
        }
    }
    if (!have_tr) {
        throw IoError(path.string() + ": malformed KITTI calib: no 'Tr:' (LiDAR -> camera 0) line");
    }
    return calib;
}

void writeKittiCalib(const std::filesystem::path& path, const KittiCalib& calib) {
    std::string text;
    char buffer[64];
    const auto line = [&](const std::string& key, const Mat34d& m) {
        text += key + ":";
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) {
                std::snprintf(buffer, sizeof(buffer), " %.17g", m(r, c));
                text += buffer;
            }
        }
        text += "\n";
    };
    for (int k = 0; k < 4; ++k) {
        if (calib.P[k]) line("P" + std::to_string(k), *calib.P[k]);
    }
    line("Tr", calib.Tr.matrix().topRows<3>());
    writeFileAtomically(path, text);
}

void writeCameraCalib(const std::filesystem::path& path, const CameraCalib& calib) {
    const CameraIntrinsics& K = calib.intrinsics;
    char buffer[64];
    const auto numbers = [&](const std::string& key, const std::vector<double>& values) {
        std::string line = key + ":";
        for (const double v : values) {
            std::snprintf(buffer, sizeof(buffer), " %.17g", v);
            line += buffer;
        }
        return line + "\n";
    };
    std::string text = numbers("K", {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1});
    text += numbers("D", std::vector<double>(K.distortion.begin(), K.distortion.end()));
    std::vector<double> T;
    const Eigen::Matrix4d M = calib.T_C_L.matrix();
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) T.push_back(M(r, c));
    }
    text += numbers("T", T);
    writeFileAtomically(path, text);
}

CameraIntrinsics intrinsicsOfProjection(const Mat34d& P, const std::string& what) {
    const Mat3d K = P.leftCols<3>();
    if (!(K(0, 0) > 0) || !(K(1, 1) > 0) || std::abs(K(0, 1)) > 1e-9 || std::abs(K(1, 0)) > 1e-9 ||
        std::abs(K(2, 0)) > 1e-9 || std::abs(K(2, 1)) > 1e-9 || std::abs(K(2, 2) - 1.0) > 1e-9) {
        throw InvalidInput(what +
                           ": projection matrix is not K [I | t] with K upper triangular, no "
                           "skew, positive focal lengths and K(2,2) = 1");
    }
    CameraIntrinsics intrinsics;
    intrinsics.fx = K(0, 0);
    intrinsics.fy = K(1, 1);
    intrinsics.cx = K(0, 2);
    intrinsics.cy = K(1, 2);
    return intrinsics;
}

Camera kittiCamera(const Mat34d& P_k, const Isometry3d& Tr, const std::string& image_folder,
                   const std::string& semantic_folder) {
    Camera camera;
    camera.name = image_folder;
    camera.semantic_name = semantic_folder;
    camera.intrinsics = intrinsicsOfProjection(P_k, "camera " + image_folder);
    // docs/DATA.md: P_k = K_k [I | t_k]  =>  t_k = K_k^-1 P_k[:,3], T_Ck_C0 = [I | t_k].
    const Mat3d K = P_k.leftCols<3>();
    const Vec3d t_k = K.triangularView<Eigen::Upper>().solve(Vec3d(P_k.col(3)));
    Isometry3d T_Ck_C0 = Isometry3d::Identity();
    T_Ck_C0.translation() = t_k;
    camera.T_C_L = T_Ck_C0 * Tr;
    return camera;
}

CameraCalib readCameraCalib(const std::filesystem::path& path) {
    CameraCalib calib;
    bool have_k = false, have_t = false;
    for (const CalibLine& line : readCalibLines(path)) {
        if (line.key == "K") {
            requireCount(path, line, {9});
            const auto& v = line.values;
            if (!(v[0] > 0) || !(v[4] > 0)) {
                throw IoError(detail::fileLine(path, line.line_number) +
                              ": K must have positive focal lengths fx (K[0]) and fy (K[4])");
            }
            calib.intrinsics.fx = v[0];
            calib.intrinsics.fy = v[4];
            calib.intrinsics.cx = v[2];
            calib.intrinsics.cy = v[5];
            have_k = true;
        } else if (line.key == "D") {
            requireCount(path, line, {0, 4, 5});
            for (std::size_t i = 0; i < line.values.size(); ++i) {
                calib.intrinsics.distortion[i] = line.values[i];
            }
        } else if (line.key == "T") {
            requireCount(path, line, {12, 16});
            calib.T_C_L =
                isometryFromRowMajor(line.values, detail::fileLine(path, line.line_number));
            have_t = true;
        }
    }
    if (!have_k || !have_t) {
        throw IoError(path.string() + ": camera calibration needs a 'K:' line and a 'T:' line");
    }
    return calib;
}

}  // namespace vdbmap
