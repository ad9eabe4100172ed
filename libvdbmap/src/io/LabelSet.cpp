// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/LabelSet.h"

#include <cmath>
#include <sstream>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"

namespace vdbmap {
namespace {

struct DefaultClass {
    int id;
    const char* name;
    int r, g, b;
};

// docs/DATA.md "Semantic classes (default label set)": Cityscapes trainIds plus lane markings.
constexpr DefaultClass kDefaultClasses[] = {
    {0, "road", 128, 64, 128},
    {1, "sidewalk", 244, 35, 232},
    {2, "building", 70, 70, 70},
    {3, "wall", 102, 102, 156},
    {4, "fence", 190, 153, 153},
    {5, "pole", 153, 153, 153},
    {6, "traffic light", 250, 170, 30},
    {7, "traffic sign", 220, 220, 0},
    {8, "vegetation", 107, 142, 35},
    {9, "terrain", 152, 251, 152},
    {10, "sky", 70, 130, 180},
    {11, "person", 220, 20, 60},
    {12, "rider", 255, 0, 0},
    {13, "car", 0, 0, 142},
    {14, "truck", 0, 0, 70},
    {15, "bus", 0, 60, 100},
    {16, "train", 0, 80, 100},
    {17, "motorcycle", 0, 0, 230},
    {18, "bicycle", 119, 11, 32},
    {19, "lane marking", 255, 255, 255},
    {20, "other object", 255, 128, 0},
};

}  // namespace

LabelSet LabelSet::defaults() {
    LabelSet set;
    set.index_.fill(-1);
    for (const DefaultClass& c : kDefaultClasses) {
        LabelClass label;
        label.id = static_cast<std::uint8_t>(c.id);
        label.name = c.name;
        label.rgb = {static_cast<std::uint8_t>(c.r), static_cast<std::uint8_t>(c.g),
                     static_cast<std::uint8_t>(c.b)};
        set.index_[label.id] = static_cast<int>(set.classes_.size());
        set.classes_.push_back(label);
    }
    return set;
}

LabelSet LabelSet::fromFile(const std::filesystem::path& path) {
    const std::string text = detail::readWholeFile(path);
    LabelSet set;
    set.index_.fill(-1);
    std::istringstream lines(text);
    std::string line;
    std::size_t line_number = 0;
    while (std::getline(lines, line)) {
        ++line_number;
        const std::size_t hash = line.find('#');
        std::string_view content = detail::trim(std::string_view(line).substr(0, hash));
        if (content.empty()) continue;
        const auto fail = [&](const std::string& why) {
            return IoError(detail::fileLine(path, line_number) + ": " + why + " in '" +
                           std::string(content) + "' (expected \"id, name, r g b\")");
        };
        const std::size_t c1 = content.find(',');
        const std::size_t c2 = c1 == std::string_view::npos ? c1 : content.find(',', c1 + 1);
        if (c2 == std::string_view::npos) throw fail("missing comma");
        double id = 0.0;
        if (!detail::parseDouble(detail::trim(content.substr(0, c1)), id) || !(id >= 0 && id <= 255) ||
            id != std::floor(id)) {  // NaN fails here, before any cast
            throw fail("class id is not an integer in 0..255");
        }
        const std::string name(detail::trim(content.substr(c1 + 1, c2 - c1 - 1)));
        if (name.empty()) throw fail("empty class name");
        std::vector<double> rgb;
        if (!detail::parseDoubles(detail::splitWhitespace(content.substr(c2 + 1)), 0, rgb) ||
            rgb.size() != 3) {
            throw fail("colour must be three integers r g b");
        }
        LabelClass label;
        label.id = static_cast<std::uint8_t>(id);
        label.name = name;
        for (int k = 0; k < 3; ++k) {
            if (!(rgb[k] >= 0 && rgb[k] <= 255) || rgb[k] != std::floor(rgb[k])) {
                throw fail("colour component out of 0..255");
            }
            label.rgb[k] = static_cast<std::uint8_t>(rgb[k]);
        }
        if (set.index_[label.id] >= 0) {
            throw fail("duplicate class id " + std::to_string(label.id));
        }
        // 255 is "void / unknown" by convention; it may be listed (for its name) but is not a
        // class of the set.
        if (label.id == 255) continue;
        set.index_[label.id] = static_cast<int>(set.classes_.size());
        set.classes_.push_back(label);
    }
    if (set.classes_.empty()) {
        throw IoError(path.string() + ": label set has no classes");
    }
    return set;
}

int LabelSet::indexOf(std::uint8_t id) const { return id == 255 ? -1 : index_[id]; }

std::array<std::uint8_t, 3> LabelSet::color(std::uint8_t id) const {
    const int i = indexOf(id);
    return i < 0 ? std::array<std::uint8_t, 3>{0, 0, 0} : classes_[i].rgb;
}

std::string LabelSet::name(std::uint8_t id) const {
    const int i = indexOf(id);
    if (i >= 0) return classes_[i].name;
    return id == 255 ? "void" : "unknown(" + std::to_string(id) + ")";
}

}  // namespace vdbmap
