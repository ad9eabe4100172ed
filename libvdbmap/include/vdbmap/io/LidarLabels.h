// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vdbmap {

/// Per-point LiDAR labels in SemanticKITTI's `.label` format (docs/DATA.md): one little-endian
/// uint32 per point of the scan, in its order; the lower 16 bits are the class id, the upper
/// 16 bits the instance id.
struct LidarLabels {
    std::vector<std::uint32_t> raw;  ///< as stored

    std::size_t size() const { return raw.size(); }
    static std::uint16_t classOf(std::uint32_t value) { return value & 0xFFFFu; }
    static std::uint16_t instanceOf(std::uint32_t value) { return value >> 16; }
};

/// Parses the bytes of a `.label` file. `name` (the file) goes into the message. Throws
/// IoError if `size` is not a multiple of 4 (a truncated file). No other check: every uint32
/// is a valid entry. `data` may be null when `size` is 0.
LidarLabels parseLidarLabels(const std::uint8_t* data, std::size_t size, const std::string& name);

/// Reads a `.label` file. Throws IoError naming the file (missing, unreadable, truncated).
LidarLabels readLidarLabels(const std::filesystem::path& path);

/// Writes a `.label` file, atomically. Throws IoError.
void writeLidarLabels(const std::filesystem::path& path, const LidarLabels& labels);

/// Throws IoError naming both files and both counts if the label file does not hold one entry
/// per point of its scan: "<labels>: 1000 labels but the scan <scan> has 1001 points".
void checkLabelCount(std::size_t labels, const std::filesystem::path& labels_path,
                     std::size_t points, const std::filesystem::path& scan_path);

/// A map from source class ids (SemanticKITTI's own ids, a network's classes) to the ids of
/// the label set. Text file, one entry per line: `source_id target_id`, optionally followed
/// by a comment; `#` starts a comment; target 255 is void (the point does not vote). Source
/// ids are 0..65535, targets 0..255. Without a file, `identity()` maps id -> id for ids
/// 0..255 and knows no larger id, so that labels already in our ids need no map.
class LabelMap {
public:
    /// Every source id 0..255 maps to itself; ids above 255 are unknown.
    static LabelMap identity();
    /// SemanticKITTI's raw ids -> docs/DATA.md's default label set (the table of
    /// config/label_maps/semantickitti.txt), named "semantickitti".
    static LabelMap semanticKitti();
    /// Parses the text of a map file. Throws IoError naming `name`, the line and the text of a
    /// malformed line, an id out of range, or a source id given twice.
    static LabelMap parse(const std::string& text, const std::string& name);
    /// Reads a map file. Throws IoError naming the file.
    static LabelMap fromFile(const std::filesystem::path& path);

    /// True if the map knows `source`.
    bool contains(std::uint16_t source) const { return known_[source] != 0; }
    /// Target of a known source id (255 = void). Call contains() first.
    std::uint8_t operator()(std::uint16_t source) const { return target_[source]; }
    /// Number of source ids the map knows.
    std::size_t size() const;
    /// Same ids mapped to the same targets (names aside).
    bool operator==(const LabelMap& other) const;
    /// Where the map came from ("identity" or the file name), for messages.
    const std::string& name() const { return name_; }

private:
    std::vector<std::uint8_t> target_ = std::vector<std::uint8_t>(65536, 255);
    std::vector<std::uint8_t> known_ = std::vector<std::uint8_t>(65536, 0);
    std::string name_ = "identity";
};

/// Maps the class part of every entry of `labels` (read from `labels_path`) through `map`.
/// Throws IoError naming the label file, the map file, the unknown source id and how many
/// points carry it, if an id is missing from the map (an id the map sends to 255 is fine).
std::vector<std::uint8_t> mapLidarLabels(const LidarLabels& labels,
                                         const std::filesystem::path& labels_path,
                                         const LabelMap& map);

}  // namespace vdbmap
