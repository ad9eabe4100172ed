// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/LidarLabels.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {

LidarLabels parseLidarLabels(const std::uint8_t* data, std::size_t size, const std::string& name) {
    if (size % 4 != 0) {
        throw IoError(name + ": a .label file holds 4 bytes per point, but it has " +
                      std::to_string(size) + " bytes (truncated?)");
    }
    LidarLabels labels;
    labels.raw.resize(size / 4);
    for (std::size_t i = 0; i < labels.raw.size(); ++i) {
        const std::uint8_t* b = data + 4 * i;
        labels.raw[i] = static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
                        (static_cast<std::uint32_t>(b[2]) << 16) |
                        (static_cast<std::uint32_t>(b[3]) << 24);
    }
    return labels;
}

LidarLabels readLidarLabels(const std::filesystem::path& path) {
    const std::string bytes = detail::readWholeFile(path);
    return parseLidarLabels(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
                            path.string());
}

void writeLidarLabels(const std::filesystem::path& path, const LidarLabels& labels) {
    std::string bytes(labels.raw.size() * 4, '\0');
    for (std::size_t i = 0; i < labels.raw.size(); ++i) {
        for (int k = 0; k < 4; ++k) {
            bytes[4 * i + k] = static_cast<char>((labels.raw[i] >> (8 * k)) & 0xFFu);
        }
    }
    AtomicFile file(path);
    {
        std::ofstream out(file.tempPath(), std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        if (!out) throw IoError(path.string() + ": write failed");
    }
    file.commit();
}

void checkLabelCount(std::size_t labels, const std::filesystem::path& labels_path,
                     std::size_t points, const std::filesystem::path& scan_path) {
    if (labels == points) return;
    throw IoError(labels_path.string() + ": " + std::to_string(labels) +
                  " labels but the scan " + scan_path.string() + " has " +
                  std::to_string(points) + " points (one label per point is required)");
}

LabelMap LabelMap::identity() {
    LabelMap map;
    for (int id = 0; id < 256; ++id) {
        map.target_[id] = static_cast<std::uint8_t>(id);
        map.known_[id] = 1;
    }
    return map;
}

LabelMap LabelMap::semanticKitti() {
    // semantic-kitti.yaml `labels` -> docs/DATA.md ids (255 = void).
    static constexpr std::uint16_t kTable[][2] = {
        {0, 255},  {1, 255},  {10, 13},  {11, 18},  {13, 15},  {15, 17},  {16, 16},
        {18, 14},  {20, 14},  {30, 11},  {31, 12},  {32, 12},  {40, 0},   {44, 0},
        {48, 1},   {49, 9},   {50, 2},   {51, 4},   {52, 3},   {60, 19},  {70, 8},
        {71, 8},   {72, 9},   {80, 5},   {81, 7},   {99, 20},  {252, 13}, {253, 12},
        {254, 11}, {255, 12}, {256, 16}, {257, 15}, {258, 14}, {259, 14}};
    LabelMap map;
    map.name_ = "semantickitti";
    for (const auto& [source, target] : kTable) {
        map.known_[source] = 1;
        map.target_[source] = static_cast<std::uint8_t>(target);
    }
    return map;
}

bool LabelMap::operator==(const LabelMap& other) const {
    return known_ == other.known_ && target_ == other.target_;
}

namespace {

bool parseId(const std::string& token, long max, long& value) {
    if (token.empty() || token.size() > 6) return false;
    if (!std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return false;
    }
    value = std::stol(token);
    return value <= max;
}

}  // namespace

LabelMap LabelMap::parse(const std::string& text, const std::string& name) {
    LabelMap map;
    map.name_ = name;
    std::istringstream in(text);
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        const std::string content = line.substr(0, line.find('#'));
        std::istringstream fields(content);
        std::string a, b, extra;
        if (!(fields >> a)) continue;  // blank or comment
        const auto where = [&] { return name + ":" + std::to_string(line_no) + ": '" + line + "'"; };
        if (!(fields >> b) || (fields >> extra)) {
            throw IoError(where() + ": expected 'source_id target_id'");
        }
        long source = 0, target = 0;
        if (!parseId(a, 65535, source)) {
            throw IoError(where() + ": source id '" + a + "' is not an integer in 0..65535");
        }
        if (!parseId(b, 255, target)) {
            throw IoError(where() + ": target id '" + b + "' is not an integer in 0..255");
        }
        if (map.known_[source]) {
            throw IoError(where() + ": source id " + a + " is mapped twice");
        }
        map.known_[source] = 1;
        map.target_[source] = static_cast<std::uint8_t>(target);
    }
    return map;
}

LabelMap LabelMap::fromFile(const std::filesystem::path& path) {
    return parse(detail::readWholeFile(path), path.string());
}

std::size_t LabelMap::size() const {
    return static_cast<std::size_t>(std::count(known_.begin(), known_.end(), 1));
}

std::vector<std::uint8_t> mapLidarLabels(const LidarLabels& labels,
                                         const std::filesystem::path& labels_path,
                                         const LabelMap& map) {
    std::vector<std::uint8_t> out(labels.size());
    std::map<std::uint16_t, std::size_t> unknown;  // source id -> points
    for (std::size_t i = 0; i < labels.size(); ++i) {
        const std::uint16_t source = LidarLabels::classOf(labels.raw[i]);
        if (!map.contains(source)) {
            ++unknown[source];
            continue;
        }
        out[i] = map(source);
    }
    if (!unknown.empty()) {
        const auto& [id, count] = *unknown.begin();
        throw IoError(labels_path.string() + ": class id " + std::to_string(id) + " (" +
                      std::to_string(count) + " of " + std::to_string(labels.size()) +
                      " points; " + std::to_string(unknown.size()) +
                      " unknown ids in all) is not in the label map " + map.name() +
                      " (" + std::to_string(map.size()) +
                      " ids); add it, mapped to 255 if it is void");
    }
    return out;
}

}  // namespace vdbmap
