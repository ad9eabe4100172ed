// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vdbmap {

/// A semantic label set: id, name, colour. The default is docs/DATA.md's table (Cityscapes trainIds
/// 0-18, 19 lane marking, 20 other object; 255 void / unknown).
struct LabelClass {
    std::uint8_t id = 0;
    std::string name;
    std::array<std::uint8_t, 3> rgb{0, 0, 0};
};

class LabelSet {
public:
    /// docs/DATA.md's default set (21 classes, not counting 255).
    static LabelSet defaults();
    /// Reads lines "id, name, r g b" ('#' comments). Throws IoError naming file and line.
    static LabelSet fromFile(const std::filesystem::path& path);

    const std::vector<LabelClass>& classes() const { return classes_; }
    std::size_t size() const { return classes_.size(); }
    /// Index of class id in classes(), or -1 (255 and unknown ids).
    int indexOf(std::uint8_t id) const;
    /// Colour of an id; black for 255 or an unknown id.
    std::array<std::uint8_t, 3> color(std::uint8_t id) const;
    std::string name(std::uint8_t id) const;

private:
    std::vector<LabelClass> classes_;
    std::array<int, 256> index_{};
};

}  // namespace vdbmap
