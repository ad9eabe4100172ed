// SPDX-License-Identifier: Apache-2.0
// vdbmap-sim --layout: a simulated sequence as the KITTI odometry, SemanticKITTI and KITTI-360
// downloads lay it out (docs/DATA.md).
#include "vdbmap/sim/SimLayout.h"

#include <algorithm>
#include <system_error>

#include "sim/SimLayoutWriters.h"
#include "vdbmap/Error.h"

namespace vdbmap {
namespace {

namespace fs = std::filesystem;

std::string sequenceNumber(const SimLayoutOptions& layout) {
    return layout.sequence.empty() ? "00" : layout.sequence;
}

// Phase 1: the layout's name and sequence, and the options the layout decides.
void checkLayout(SimOptions& options, const SimLayoutOptions& layout) {
    const auto& names = simLayoutNames();
    if (std::find(names.begin(), names.end(), layout.layout) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw ConfigError("vdbmap-sim: --layout must be one of " + list + ", got '" +
                          layout.layout + "'");
    }
    if (layout.layout == "sequence") return;
    if (options.rig != "kitti") {
        throw ConfigError("vdbmap-sim: --layout " + layout.layout +
                          " is a layout of the kitti rig, not of --rig " + options.rig);
    }
    const std::string& s = layout.sequence;
    const bool path_like = s.find('/') != std::string::npos || s == "." || s == "..";
    if (path_like) {
        throw ConfigError("vdbmap-sim: --sequence '" + s + "' must be a folder name");
    }
    if (layout.layout == "kitti-odometry") options.lidar_labels = false;  // not in the download
    if (layout.layout == "semantic-kitti") options.images = false;        // LiDAR only
    if (layout.layout == "kitti360") options.cameras = 2;  // both perspective cameras
}

// Phase 2, the KITTI layouts: dataset/sequences/NN (+ dataset/poses/NN.txt for odometry).
void arrangeKitti(const fs::path& sequence_dir, const SimLayoutOptions& layout,
                  const fs::path& out_dir) {
    const std::string nn = sequenceNumber(layout);
    const fs::path target = out_dir / simLayoutDatasetPath(layout);
    for (const char* name : {"velodyne", "calib.txt", "times.txt"}) {
        sim::moveIfPresent(sequence_dir / name, target / name);
    }
    if (layout.layout == "kitti-odometry") {
        // The odometry download keeps the poses apart, one file per sequence.
        sim::moveIfPresent(sequence_dir / "poses.txt",
                           out_dir / "dataset" / "poses" / (nn + ".txt"));
        for (const char* name : {"image_2", "image_3"}) {
            sim::moveIfPresent(sequence_dir / name, target / name);
        }
    } else {
        sim::moveIfPresent(sequence_dir / "poses.txt", target / "poses.txt");
        sim::moveIfPresent(sequence_dir / "labels", target / "labels");
    }
    sim::moveGroundTruth(sequence_dir, out_dir);
}

}  // namespace

namespace sim {

void moveIfPresent(const fs::path& from, const fs::path& to) {
    std::error_code ec;
    if (!fs::exists(from, ec)) return;
    fs::create_directories(to.parent_path(), ec);
    fs::rename(from, to, ec);
    if (ec) {
        throw IoError("vdbmap-sim: cannot move " + from.string() + " to " + to.string() + ": " +
                      ec.message());
    }
}

void moveGroundTruth(const fs::path& sequence_dir, const fs::path& out_dir) {
    moveIfPresent(sequence_dir / "gt", out_dir / "gt");
    for (const char* name : {"vignetting.txt", "exposure.txt"}) {
        moveIfPresent(sequence_dir / name, out_dir / "gt" / name);
    }
}

}  // namespace sim

const std::vector<std::string>& simLayoutNames() {
    static const std::vector<std::string> names{"sequence", "kitti-odometry", "semantic-kitti",
                                                "kitti360"};
    return names;
}

fs::path simLayoutDatasetPath(const SimLayoutOptions& layout) {
    if (layout.layout == "kitti-odometry" || layout.layout == "semantic-kitti") {
        return fs::path("dataset") / "sequences" / sequenceNumber(layout);
    }
    return ".";
}

SimSummary writeSimLayout(SimOptions options, const SimLayoutOptions& layout,
                          const fs::path& out_dir) {
    checkLayout(options, layout);
    if (layout.layout == "sequence") return writeSimSequence(options, out_dir);
    // The sequence goes to a hidden folder of out_dir (same file system: the moves are
    // renames), which is removed once its files are in place.
    const fs::path sequence_dir = out_dir / ".sequence";
    std::error_code ec;
    fs::remove_all(sequence_dir, ec);
    const SimSummary summary = writeSimSequence(options, sequence_dir);
    if (layout.layout == "kitti360") {
        sim::arrangeKitti360(sequence_dir, layout, out_dir);
    } else {
        arrangeKitti(sequence_dir, layout, out_dir);
    }
    fs::remove_all(sequence_dir, ec);
    if (ec)
        throw IoError("vdbmap-sim: cannot remove " + sequence_dir.string() + ": " + ec.message());
    return summary;
}

}  // namespace vdbmap
