// SPDX-License-Identifier: Apache-2.0
// The moving-point scores of a run: its dynamic_points.ply against the simulator's labels.
#include <cstring>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "vdbmap/Error.h"
#include "vdbmap/eval/TrafficMetrics.h"
#include "vdbmap/io/LidarLabels.h"

namespace vdbmap {

namespace fs = std::filesystem;

namespace {

struct PlyProperty {
    std::string name;
    std::string type;
    std::size_t offset = 0;
};

std::size_t typeSize(const std::string& type) {
    static const std::map<std::string, std::size_t> sizes{
        {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
        {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
        {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

// One value of a property as a double (little-endian host, as the format requires).
double valueAt(const char* record, const PlyProperty& p) {
    const char* s = record + p.offset;
    const std::string& t = p.type;
    const auto get = [s](auto v) {
        std::memcpy(&v, s, sizeof(v));
        return static_cast<double>(v);
    };
    if (t == "char" || t == "int8") return get(std::int8_t{});
    if (t == "uchar" || t == "uint8") return get(std::uint8_t{});
    if (t == "short" || t == "int16") return get(std::int16_t{});
    if (t == "ushort" || t == "uint16") return get(std::uint16_t{});
    if (t == "int" || t == "int32") return get(std::int32_t{});
    if (t == "uint" || t == "uint32") return get(std::uint32_t{});
    if (t == "float" || t == "float32") return get(float{});
    return get(double{});
}

std::string labelFileStem(std::size_t f) {
    std::ostringstream s;
    s << std::setw(6) << std::setfill('0') << f;
    return s.str();
}

}  // namespace

std::vector<RemovedPoint> readRemovedPointsPly(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path.string() + ": cannot open");
    const auto fail = [&](const std::string& what) { return IoError(path.string() + ": " + what); };
    std::string line;
    if (!std::getline(in, line) || line != "ply") throw fail("not a PLY file");
    std::size_t count = 0, record_size = 0;
    std::vector<PlyProperty> props;
    bool in_vertex = false, seen_vertex = false;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ss(line);
        std::string word;
        ss >> word;
        if (word == "end_header") break;
        if (word == "format") {
            std::string format;
            ss >> format;
            if (format != "binary_little_endian") {
                throw fail("format '" + format + "', expected binary_little_endian");
            }
        } else if (word == "element") {
            std::string name;
            ss >> name;
            if (seen_vertex) {
                in_vertex = false;  // elements after the vertices are not read
                continue;
            }
            if (name != "vertex") throw fail("element '" + name + "' before the vertices");
            ss >> count;
            in_vertex = seen_vertex = true;
        } else if (word == "property" && in_vertex) {
            PlyProperty p;
            ss >> p.type >> p.name;
            const std::size_t size = typeSize(p.type);
            if (size == 0) throw fail("vertex property '" + p.name + "' of type '" + p.type + "'");
            p.offset = record_size;
            record_size += size;
            props.push_back(p);
        }
    }
    if (!seen_vertex) throw fail("no vertex element");
    const auto find = [&](const char* name) {
        for (const auto& p : props) {
            if (p.name == name) return p;
        }
        throw fail(std::string("no vertex property '") + name + "'");
    };
    const PlyProperty frame = find("frame"), index = find("index");
    for (const char* xyz : {"x", "y", "z"}) find(xyz);
    std::vector<char> body(count * record_size);
    in.read(body.data(), static_cast<std::streamsize>(body.size()));
    if (static_cast<std::size_t>(in.gcount()) != body.size()) {
        throw fail("truncated: " + std::to_string(count) + " vertices of " +
                   std::to_string(record_size) + " bytes announced");
    }
    std::vector<RemovedPoint> out(count);
    for (std::size_t i = 0; i < count; ++i) {
        const char* r = body.data() + i * record_size;
        out[i].frame = static_cast<std::uint32_t>(valueAt(r, frame));
        out[i].index = static_cast<std::uint32_t>(valueAt(r, index));
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
