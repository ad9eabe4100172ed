// SPDX-License-Identifier: Apache-2.0
#include "Tileset.h"

#include <cmath>

namespace vdbmap::tiles3d {
namespace {

using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
/// Boxes are grown by this much, so that a flat tile has a volume.
constexpr double kBoxPad_m = 0.01;

json boxJson(const Bounds& b) {
    const Eigen::Vector3d c = 0.5 * (b.min_W + b.max_W);
    const Eigen::Vector3d h = (0.5 * (b.max_W - b.min_W)).array() + kBoxPad_m;
    return json::array({c.x(), c.y(), c.z(), h.x(), 0.0, 0.0, 0.0, h.y(), 0.0, 0.0, 0.0, h.z()});
}

json tileJson(const TileNode& node) {
    json t;
    t["boundingVolume"] = {{"box", boxJson(node.box_W)}};
    t["geometricError"] = node.geometric_error_m;
    t["refine"] = "REPLACE";
    if (!node.content_uri.empty()) t["content"] = {{"uri", node.content_uri}};
    if (!node.children.empty()) {
        json children = json::array();
        for (const TileNode& c : node.children) children.push_back(tileJson(c));
        t["children"] = children;
    }
    return t;
}

}  // namespace

Eigen::Vector3d ecefFromGeodetic(double latitude_deg, double longitude_deg, double altitude_m) {
    constexpr double a = 6378137.0, f = 1.0 / 298.257223563;
    const double e2 = f * (2 - f);
    const double lat = latitude_deg * kPi / 180, lon = longitude_deg * kPi / 180;
    const double n = a / std::sqrt(1 - e2 * std::sin(lat) * std::sin(lat));
    return {(n + altitude_m) * std::cos(lat) * std::cos(lon),
            (n + altitude_m) * std::cos(lat) * std::sin(lon),
            (n * (1 - e2) + altitude_m) * std::sin(lat)};
}

Eigen::Matrix3d zUpFromW(int up_axis, int up_sign) {
    const Eigen::Vector3d up = (up_sign < 0 ? -1.0 : 1.0) * Eigen::Vector3d::Unit(up_axis);
    const Eigen::Vector3d first = Eigen::Vector3d::Unit((up_axis + 1) % 3);
    Eigen::Matrix3d R;
    R.row(0) = first.transpose();
    R.row(1) = up.cross(first).transpose();
    R.row(2) = up.transpose();
    return R;
}

Eigen::Matrix4d rootTransform(const Georef& georef, int up_axis, int up_sign) {
    const Eigen::Matrix3d R_Z_W = zUpFromW(up_axis, up_sign);
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    T.topLeftCorner<3, 3>() = R_Z_W;
    if (!georef.enabled) return T;
    const double h = georef.heading_deg * kPi / 180;
    Eigen::Matrix3d R_ENU_Z;  // W's y at compass heading h: y = (sin h, cos h), x = (cos h, -sin h)
    R_ENU_Z << std::cos(h), std::sin(h), 0, -std::sin(h), std::cos(h), 0, 0, 0, 1;
    const double lat = georef.latitude_deg * kPi / 180, lon = georef.longitude_deg * kPi / 180;
    Eigen::Matrix3d R_ECEF_ENU;
    R_ECEF_ENU.col(0) << -std::sin(lon), std::cos(lon), 0;
    R_ECEF_ENU.col(1) << -std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat);
    R_ECEF_ENU.col(2) << std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat);
    Eigen::Matrix4d G = Eigen::Matrix4d::Identity();
    G.topLeftCorner<3, 3>() = R_ECEF_ENU * R_ENU_Z;
    G.topRightCorner<3, 1>() = ecefFromGeodetic(georef.latitude_deg, georef.longitude_deg, georef.altitude_m);
    return G * T;
}

std::string tilesetJson(const TileNode& root, const Eigen::Matrix4d& root_transform,
                        const json& extras) {
    json tileset;
    tileset["asset"] = {{"version", "1.1"}, {"generator", "vdbmap export.3dtiles"}};
    tileset["geometricError"] = std::max(root.geometric_error_m,
                                         (root.box_W.max_W - root.box_W.min_W).norm());
    json r = tileJson(root);
    if (!root_transform.isIdentity(0)) {
        json m = json::array();
        for (int c = 0; c < 4; ++c)
            for (int row = 0; row < 4; ++row) m.push_back(root_transform(row, c));
        r["transform"] = m;
    }
    tileset["root"] = r;
    if (!extras.is_null()) tileset["extras"] = extras;
    return tileset.dump(1);
}

}  // namespace vdbmap::tiles3d
