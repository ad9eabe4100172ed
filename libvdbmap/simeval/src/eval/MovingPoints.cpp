// SPDX-License-Identifier: Apache-2.0
// The moving-point scores of a run: its dynamic_points.ply against the simulator's labels.
#include <cstring>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "io/FileUtil.h"
#include "io/PlyFormat.h"
#include "vdbmap/Error.h"
#include "vdbmap/eval/TrafficMetrics.h"
#include "vdbmap/io/LidarLabels.h"

namespace vdbmap {

namespace fs = std::filesystem;

namespace {

std::string labelFileStem(std::size_t f) {
    std::ostringstream s;
    s << std::setw(6) << std::setfill('0') << f;
    return s.str();
}

}  // namespace

std::vector<RemovedPoint> readRemovedPointsPly(const fs::path& path) {
    // The project's PLY reader (io/PlyFormat.h): any format, properties in any order, other
    // properties and elements skipped; truncated or malformed data is an IoError naming the file.
    const std::string bytes = detail::readWholeFile(path);
    const detail::PlyHeader header = detail::parsePlyHeader(bytes, path);
    if (header.find("vertex") < 0) throw IoError(path.string() + ": no vertex element");
    detail::PlyDataReader reader(bytes, header, path);
    std::vector<RemovedPoint> out;
    std::vector<double> scalars;
    std::vector<std::vector<double>> lists;
    for (const detail::PlyElement& element : header.elements) {
        const bool vertex = element.name == "vertex";
        // Slot of a scalar property in PlyDataReader's `scalars` (lists are not counted).
        const auto slot = [&](const char* name) {
            int k = 0;
            for (const detail::PlyProperty& p : element.properties) {
                if (p.is_list) continue;
                if (p.name == name) return k;
                ++k;
            }
            throw IoError(path.string() + ": no vertex property '" + name + "'");
        };
        int frame = -1, index = -1;
        if (vertex) {
            frame = slot("frame");
            index = slot("index");
            for (const char* xyz : {"x", "y", "z"}) slot(xyz);
            out.resize(element.count);
        }
        for (std::size_t i = 0; i < element.count; ++i) {
            reader.read(element, scalars, lists);
            if (!vertex) continue;
            out[i].frame = static_cast<std::uint32_t>(scalars[static_cast<std::size_t>(frame)]);
            out[i].index = static_cast<std::uint32_t>(scalars[static_cast<std::size_t>(index)]);
        }
    }
    return out;
}

MovingTruth readMovingTruth(const fs::path& labels_dir, std::size_t frames) {
    MovingTruth truth(frames);
    for (std::size_t f = 0; f < frames; ++f) {
        const LidarLabels labels = readLidarLabels(labels_dir / (labelFileStem(f) + ".label"));
        truth[f].resize(labels.size());
        for (std::size_t i = 0; i < labels.size(); ++i) {
            const std::uint32_t v = labels.raw[i];
            const std::uint16_t cls = LidarLabels::classOf(v);
            truth[f][i] = LidarLabels::instanceOf(v) != 0 || (cls >= 252 && cls <= 259);
        }
    }
    return truth;
}

fs::path findSimLabelsDir(const fs::path& gt_dir) {
    std::error_code ec;
    if (fs::is_directory(gt_dir / "labels", ec)) return gt_dir / "labels";
    const fs::path seq = gt_dir.parent_path();
    if (fs::is_directory(seq / "labels", ec)) return seq / "labels";
    const fs::path sequences = seq / "dataset" / "sequences";
    if (fs::is_directory(sequences, ec)) {
        std::set<fs::path> found;  // sorted: the first sequence with labels
        for (const auto& e : fs::directory_iterator(sequences, ec)) {
            if (fs::is_directory(e.path() / "labels", ec)) found.insert(e.path() / "labels");
        }
        if (!found.empty()) return *found.begin();
    }
    return {};
}

MovingPointScores scoreRemovedPoints(const MovingTruth& truth,
                                     const std::vector<RemovedPoint>& removed) {
    MovingPointScores s;
    for (const auto& frame : truth) {
        for (std::uint8_t m : frame) (m ? s.moving_points : s.static_points)++;
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
    for (const RemovedPoint& r : removed) {
        if (!seen.insert({r.frame, r.index}).second) {
            ++s.removed_duplicates;
            continue;
        }
        ++s.removed;
        if (r.frame >= truth.size() || r.index >= truth[r.frame].size()) {
            ++s.removed_unmatched;
        } else if (truth[r.frame][r.index]) {
            ++s.removed_moving;
        } else {
            ++s.removed_static;
        }
    }
    s.recall = s.moving_points > 0
                   ? static_cast<double>(s.removed_moving) / static_cast<double>(s.moving_points)
                   : 0.0;
    s.precision = s.removed > 0
                      ? static_cast<double>(s.removed_moving) / static_cast<double>(s.removed)
                      : 0.0;
    s.static_retention = s.static_points > 0 ? 1.0 - static_cast<double>(s.removed_static) /
                                                         static_cast<double>(s.static_points)
                                             : 1.0;
    return s;
}

}  // namespace vdbmap
