// SPDX-License-Identifier: Apache-2.0
// KITTI-360's data_poses/<drive>/poses.txt and the timestamps.txt of its sensor folders.
#include <cmath>
#include <cstdio>
#include <ctime>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/Kitti360.h"

namespace vdbmap {
namespace {

/// "YYYY-MM-DD HH:MM:SS[.fffffffff]": whole seconds since 1970 (UTC) and the fraction of a
/// second; false if malformed.
bool parseTimestamp(const std::string& date, const std::string& time, long long& whole_s,
                    double& fraction_s) {
    // Digits and separators only: sscanf's %lf would also take "0x.5", "inf" or "nan".
    const auto only = [](const std::string& text, const char* separators) {
        return text.find_first_not_of(std::string("0123456789") + separators) == std::string::npos;
    };
    if (!only(date, "-") || !only(time, ":.")) return false;
    int y = 0, mo = 0, d = 0, h = 0, mi = 0, consumed = 0;
    if (std::sscanf(date.c_str(), "%4d-%2d-%2d%n", &y, &mo, &d, &consumed) != 3 ||
        consumed != static_cast<int>(date.size())) {
        return false;
    }
    double s = 0.0;
    consumed = 0;
    if (std::sscanf(time.c_str(), "%2d:%2d:%lf%n", &h, &mi, &s, &consumed) != 3 ||
        consumed != static_cast<int>(time.size())) {
        return false;
    }
    if (mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 23 || mi < 0 || mi > 59 ||
        !(s >= 0.0 && s < 61.0)) {
        return false;
    }
    std::tm civil{};
    civil.tm_year = y - 1900;
    civil.tm_mon = mo - 1;
    civil.tm_mday = d;
    civil.tm_hour = h;
    civil.tm_min = mi;
    const double whole_in_minute = std::floor(s);
    whole_s = static_cast<long long>(timegm(&civil)) + static_cast<long long>(whole_in_minute);
    fraction_s = s - whole_in_minute;
    return true;
}

}  // namespace

std::vector<Kitti360Pose> readKitti360Poses(const std::filesystem::path& path) {
    std::vector<Kitti360Pose> poses;
    std::vector<double> v;
    detail::forEachLine(path, [&](const detail::TextLine& line) {
        if (line.tokens.empty()) return;
        if (!detail::parseDoubles(line.tokens, 0, v) || v.size() != 13) {
            throw IoError(detail::lineMessage(
                path, line,
                "KITTI-360 pose line must hold 13 numbers: a frame number and the row-major "
                "3x4 IMU -> world transform"));
        }
        const double frame = v[0];
        if (!(frame >= 0.0 && frame < 1e12 && std::floor(frame) == frame)) {
            throw IoError(
                detail::lineMessage(path, line, "the frame number is not a non-negative integer"));
        }
        Kitti360Pose pose;
        pose.frame = static_cast<long long>(frame);
        if (!poses.empty() && pose.frame <= poses.back().frame) {
            throw IoError(detail::lineMessage(
                path, line,
                "frame " + std::to_string(pose.frame) + " does not follow frame " +
                    std::to_string(poses.back().frame) + " (frames must increase)"));
        }
        try {
            pose.T_W_IMU = isometryFromRowMajor(std::vector<double>(v.begin() + 1, v.end()),
                                                detail::fileLine(path, line.number));
        } catch (const InvalidInput& e) {
            throw IoError(e.what());
        }
        poses.push_back(pose);
    });
    return poses;
}

void writeKitti360Poses(const std::filesystem::path& path, const std::vector<Kitti360Pose>& poses) {
    std::string text;
    char buffer[64];
    for (const Kitti360Pose& pose : poses) {
        text += std::to_string(pose.frame);
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) {
                std::snprintf(buffer, sizeof(buffer), " %.17g", pose.T_W_IMU.matrix()(r, c));
                text += buffer;
            }
        }
        text += '\n';
    }
    writeFileAtomically(path, text);
}

std::vector<double> readKitti360Timestamps(const std::filesystem::path& path) {
    std::vector<double> times;
    long long start_whole = 0;
    double start_fraction = 0.0;
    detail::forEachLine(path, [&](const detail::TextLine& line) {
        if (line.tokens.empty()) return;
        long long whole = 0;
        double fraction = 0.0;
        if (line.tokens.size() != 2 ||
            !parseTimestamp(line.tokens[0], line.tokens[1], whole, fraction)) {
            throw IoError(detail::lineMessage(
                path, line, "expected a timestamp 'YYYY-MM-DD HH:MM:SS.fffffffff'"));
        }
        if (times.empty()) {
            start_whole = whole;
            start_fraction = fraction;
        }
        times.push_back(static_cast<double>(whole - start_whole) + (fraction - start_fraction));
    });
    return times;
}

void writeKitti360Timestamps(const std::filesystem::path& path, std::int64_t start_s,
                             const std::vector<double>& seconds_since_start) {
    std::string text;
    char buffer[64];
    for (const double t : seconds_since_start) {
        long long whole = static_cast<long long>(std::floor(t));
        long long nanos = std::llround((t - static_cast<double>(whole)) * 1e9);
        if (nanos >= 1000000000LL) {
            ++whole;
            nanos -= 1000000000LL;
        }
        const std::time_t time = static_cast<std::time_t>(start_s + whole);
        std::tm civil{};
        gmtime_r(&time, &civil);
        std::snprintf(buffer, sizeof(buffer), "%04d-%02d-%02d %02d:%02d:%02d.%09lld\n",
                      civil.tm_year + 1900, civil.tm_mon + 1, civil.tm_mday, civil.tm_hour,
                      civil.tm_min, civil.tm_sec, nanos);
        text += buffer;
    }
    writeFileAtomically(path, text);
}

}  // namespace vdbmap
