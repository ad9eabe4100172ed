// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/eval/GtViews.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {

void writeGtViews(const std::filesystem::path& folder, const std::vector<GtView>& views) {
    nlohmann::json root;
    root["format"] = "vdbmap-gt-views-1";
    root["pixel_convention"] = "(0,0) is the centre of the top-left pixel";
    root["views"] = nlohmann::json::array();
    for (const auto& v : views) {
        nlohmann::json j;
        j["image"] = v.image;
        j["width"] = v.intrinsics.width;
        j["height"] = v.intrinsics.height;
        j["fx"] = v.intrinsics.fx;
        j["fy"] = v.intrinsics.fy;
        j["cx"] = v.intrinsics.cx;
        j["cy"] = v.intrinsics.cy;
        std::vector<double> m;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) m.push_back(v.T_W_C.matrix()(r, c));
        }
        j["T_W_C"] = m;
        root["views"].push_back(j);
    }
    writeFileAtomically(folder / "views.json", root.dump(2) + "\n");
}

std::vector<GtView> readGtViews(const std::filesystem::path& folder) {
    const auto path = folder / "views.json";
    std::ifstream in(path);
    if (!in) throw IoError(path.string() + ": cannot open");
    nlohmann::json root;
    try {
        in >> root;
    } catch (const std::exception& e) {
        throw IoError(path.string() + ": not valid JSON: " + e.what());
    }
    std::vector<GtView> views;
    try {
        for (const auto& j : root.at("views")) {
            GtView v;
            v.image = j.at("image").get<std::string>();
            v.intrinsics.width = j.at("width").get<int>();
            v.intrinsics.height = j.at("height").get<int>();
            v.intrinsics.fx = j.at("fx").get<double>();
            v.intrinsics.fy = j.at("fy").get<double>();
            v.intrinsics.cx = j.at("cx").get<double>();
            v.intrinsics.cy = j.at("cy").get<double>();
            const auto m = j.at("T_W_C").get<std::vector<double>>();
            if (m.size() != 12) {
                throw IoError(path.string() + ": view '" + v.image + "' T_W_C has " +
                              std::to_string(m.size()) + " numbers, expected 12");
            }
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 4; ++c) v.T_W_C.matrix()(r, c) = m[4 * r + c];
            }
            views.push_back(v);
        }
    } catch (const nlohmann::json::exception& e) {
        throw IoError(path.string() + ": " + e.what());
    }
    return views;
}

}  // namespace vdbmap
