// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/PoseIO.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {
namespace {

bool allFinite(const std::vector<double>& values) {
    for (const double v : values) {
        if (!std::isfinite(v)) return false;
    }
    return true;
}

}  // namespace

std::vector<Isometry3d> readKittiPoses(const std::filesystem::path& path) {
    std::vector<Isometry3d> poses;
    std::vector<double> values;
    detail::forEachLine(path, [&](const detail::TextLine& text_line) {
        const std::string& line = text_line.text;
        const std::size_t line_number = text_line.number;
        const std::vector<std::string>& tok = text_line.tokens;
        if (tok.empty()) return;
        if (!detail::parseDoubles(tok, 0, values) || values.size() != 12 || !allFinite(values)) {
            throw IoError(detail::fileLine(path, line_number) +
                          ": KITTI pose line must hold 12 finite numbers (row-major 3x4), got '" +
                          line.substr(0, 160) + "'");
        }
        Isometry3d T = Isometry3d::Identity();
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) T.matrix()(r, c) = values[r * 4 + c];
        }
        // A scaled or sheared "rotation" is well-formed text but not a pose (KITTI files hold
        // 6+ significant digits, so 1e-3 only refuses real errors).
        const Mat3d R = T.linear();
        const double orthogonality = (R.transpose() * R - Mat3d::Identity()).cwiseAbs().maxCoeff();
        if (!(orthogonality < 1e-3) || !(R.determinant() > 0)) {
            throw IoError(detail::fileLine(path, line_number) +
                          ": KITTI pose rotation (the left 3x3) is not a rotation: |R^T R - I| = " +
                          std::to_string(orthogonality) + ", det = " +
                          std::to_string(R.determinant()));
        }
        poses.push_back(T);
    });
    return poses;
}

std::vector<StampedPose> readTumPoses(const std::filesystem::path& path) {
    std::vector<StampedPose> poses;
    std::vector<double> v;
    detail::forEachLine(path, [&](const detail::TextLine& text_line) {
        const std::string& line = text_line.text;
        const std::size_t line_number = text_line.number;
        const std::vector<std::string>& tok = text_line.tokens;
        if (tok.empty() || tok.front().front() == '#') return;
        if (!detail::parseDoubles(tok, 0, v) || v.size() != 8 ||
            !allFinite(v)) {
            throw IoError(detail::fileLine(path, line_number) +
                          ": TUM pose line must hold 8 finite numbers 't tx ty tz qx qy qz qw', "
                          "got '" +
                          line.substr(0, 160) + "'");
        }
        Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen order: w x y z
        if (!(q.norm() >= 1e-9) || !std::isfinite(q.norm())) {  // zero, or overflows
            throw IoError(detail::fileLine(path, line_number) +
                          ": TUM pose quaternion has norm " + std::to_string(q.norm()) +
                          " (zero or too large to normalize)");
        }
        q.normalize();
        StampedPose pose;
        pose.timestamp_s = v[0];
        pose.T_W_S.linear() = q.toRotationMatrix();
        pose.T_W_S.translation() = Vec3d(v[1], v[2], v[3]);
        poses.push_back(pose);
    });
    return poses;
}

void writeKittiPoses(const std::filesystem::path& path, const std::vector<Isometry3d>& poses) {
    std::string text;
    char buffer[64];
    for (const Isometry3d& T : poses) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) {
                std::snprintf(buffer, sizeof(buffer), "%.17g", T.matrix()(r, c));
                text += buffer;
                text += (r == 2 && c == 3) ? '\n' : ' ';
            }
        }
    }
    writeFileAtomically(path, text);
}

void writeTumPoses(const std::filesystem::path& path, const std::vector<StampedPose>& poses) {
    std::string text = "# timestamp tx ty tz qx qy qz qw\n";
    char buffer[320];
    for (const StampedPose& pose : poses) {
        const Eigen::Quaterniond q(pose.T_W_S.linear());
        const Vec3d& t = pose.T_W_S.translation();
        std::snprintf(buffer, sizeof(buffer), "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                      pose.timestamp_s, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
        text += buffer;
    }
    writeFileAtomically(path, text);
}

}  // namespace vdbmap
