// SPDX-License-Identifier: Apache-2.0
#include <sstream>

#include "io/DatasetBuilder.h"
#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/PoseIO.h"

namespace vdbmap {
namespace {

std::vector<double> readTimes(const std::filesystem::path& path) {
    const std::string text = detail::readWholeFile(path);
    std::istringstream lines(text);
    std::string line;
    std::size_t line_number = 0;
    std::vector<double> times;
    while (std::getline(lines, line)) {
        ++line_number;
        const std::vector<std::string> tok = detail::splitWhitespace(line);
        if (tok.empty()) continue;
        double t = 0.0;
        if (tok.size() != 1 || !detail::parseDouble(tok[0], t)) {
            throw IoError(detail::fileLine(path, line_number) +
                          ": expected one timestamp in seconds, got '" + line.substr(0, 80) + "'");
        }
        times.push_back(t);
    }
    return times;
}

/// The poses file of a KITTI sequence `root`: `poses_file` (relative to root) if set, else
/// SEQ/poses.txt (SemanticKITTI, our simulator), else where the odometry download keeps it:
/// dataset/poses/NN.txt next to dataset/sequences/NN. Throws IoError naming the places tried.
std::filesystem::path kittiPosesPath(const std::filesystem::path& root,
                                     const std::string& poses_file) {
    std::error_code ec;
    if (!poses_file.empty()) {
        const std::filesystem::path path = DatasetBuilder::resolve(root, poses_file);
        if (!std::filesystem::is_regular_file(path, ec)) {
            throw IoError("dataset: poses_file not found: " + path.string());
        }
        return path;
    }
    const std::filesystem::path in_sequence = root / "poses.txt";
    if (std::filesystem::is_regular_file(in_sequence, ec)) return in_sequence;
    std::filesystem::path sequence = std::filesystem::absolute(root, ec).lexically_normal();
    if (sequence.filename().empty()) sequence = sequence.parent_path();  // "sequences/00/"
    const std::filesystem::path download =
        sequence.parent_path().parent_path() / "poses" / (sequence.filename().string() + ".txt");
    if (std::filesystem::is_regular_file(download, ec)) return download;
    throw IoError("KITTI poses not found: neither " + in_sequence.string() + " nor " +
                  download.string() +
                  " (the odometry download's dataset/poses/NN.txt) exists; set "
                  "dataset.poses_file to the camera-0 poses of this sequence");
}

}  // namespace

void DatasetBuilder::openKitti(Dataset& dataset) {
    const std::filesystem::path& root = dataset.root_;
    if (!dataset.config_.rig.empty()) {
        throw ConfigError(
            "dataset: the KITTI layout takes 'cameras' as a list of folder names (image_2, "
            "image_3), got " +
            std::to_string(dataset.config_.rig.size()) +
            " camera map(s); camera maps are for format 'generic'");
    }
    const std::vector<std::filesystem::path> scans = listScans(root / "velodyne", "KITTI velodyne");
    const KittiCalib calib = readKittiCalib(root / "calib.txt");
    const std::filesystem::path poses_path = kittiPosesPath(root, dataset.config_.poses_file);
    const std::vector<Isometry3d> poses_C0 = readKittiPoses(poses_path);
    dataset.poses_path_ = poses_path;
    std::vector<double> times;
    const std::filesystem::path times_path = root / "times.txt";
    std::error_code ec;
    if (std::filesystem::exists(times_path, ec)) times = readTimes(times_path);

    // Line i of poses.txt / times.txt belongs to frame number i (the zero-padded file name);
    // if the names are not numbers, to the i-th scan in name order.
    std::vector<FrameInfo> all;
    for (std::size_t k = 0; k < scans.size(); ++k) {
        FrameInfo frame;
        frame.id = scans[k].stem().string();
        frame.scan_path = scans[k];
        const long long number = frameNumber(frame.id);
        const std::size_t line = number >= 0 ? static_cast<std::size_t>(number) : k;
        if (poses_C0.size() < scans.size() || line >= poses_C0.size()) {
            throw IoError("fewer poses than scans: " + poses_path.string() + " has " +
                          std::to_string(poses_C0.size()) + " poses but " +
                          (root / "velodyne").string() + " has " + std::to_string(scans.size()) +
                          " scans (frame " + frame.id + " needs pose line " +
                          std::to_string(line + 1) + ")");
        }
        // docs/DATA.md: poses.txt holds T_W_C0; the LiDAR pose is T_W_L = T_W_C0 * Tr.
        frame.T_W_L = poses_C0[line] * calib.Tr;
        if (!times.empty()) {
            if (line >= times.size()) {
                throw IoError(times_path.string() + " has " + std::to_string(times.size()) +
                              " timestamps but frame " + frame.id + " needs line " +
                              std::to_string(line + 1));
            }
            frame.timestamp_s = times[line];
        }
        all.push_back(std::move(frame));
    }
    selectFrames(dataset, std::move(all));

    std::vector<std::string> names = dataset.config_.cameras;
    const bool explicit_names = !names.empty();
    if (!explicit_names) {
        for (const char* name : {"image_2", "image_3"}) {
            if (std::filesystem::is_directory(root / name, ec)) names.emplace_back(name);
        }
    }
    for (const std::string& name : names) {
        const char digit = name.empty() ? '\0' : name.back();
        if (name.rfind("image_", 0) != 0 || name.size() != 7 || digit < '0' || digit > '3') {
            throw ConfigError("dataset: option 'cameras' entry '" + name +
                              "' is not a KITTI camera folder (image_0 .. image_3)");
        }
        requireFolder(root / name, "KITTI camera");
        const int k = digit - '0';
        if (!calib.P[k]) {
            throw IoError((root / "calib.txt").string() + ": no 'P" + std::to_string(k) +
                          ":' line for camera folder " + name);
        }
        const std::string semantic = "semantic_" + std::string(1, digit);
        const bool has_semantic = std::filesystem::is_directory(root / semantic, ec);
        try {
            dataset.cameras_.push_back(
                kittiCamera(*calib.P[k], calib.Tr, name, has_semantic ? semantic : ""));
        } catch (const InvalidInput& e) {
            throw IoError((root / "calib.txt").string() + ": P" + std::to_string(k) + ": " +
                          e.what());
        }
        dataset.image_dirs_.push_back(root / name);
        dataset.semantic_dirs_.push_back(has_semantic ? root / semantic : std::filesystem::path());
    }
}

}  // namespace vdbmap
