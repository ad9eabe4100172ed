// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "TileMesh.h"

namespace vdbmap::tiles3d {

/// A tile of the tileset: its box in W, its content (a GLB, relative to tileset.json; "" =
/// none) and the geometric error of showing it instead of its children (metres).
struct TileNode {
    std::string content_uri;
    Bounds box_W;
    double geometric_error_m = 0;
    int level = 0;  ///< 0 = leaf (a ground tile at full resolution)
    std::vector<TileNode> children;
};

/// The optional geo-reference of W's origin (docs/tiles3d.md "Frames").
struct Georef {
    bool enabled = false;
    double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;
    /// Compass heading of W's +y axis, degrees clockwise from north (0: x east, y north).
    double heading_deg = 0;
};

/// WGS84 geodetic -> ECEF (metres).
Eigen::Vector3d ecefFromGeodetic(double latitude_deg, double longitude_deg, double altitude_m);

/// The rotation that turns W's up direction (`up_sign` times axis `up_axis`: 0 = x, 1 = y,
/// 2 = z) into +z: rows e_{(a+1)%3}, up x that, up (identity for a z-up W; KITTI's camera
/// frame, y down: (x, y, z) -> (z, -x, -y)).
Eigen::Matrix3d zUpFromW(int up_axis, int up_sign);

/// The root transform: T_ECEF_W with the geo-reference (zUpFromW, then ENU at the reference
/// point rotated by the heading, then ECEF), else zUpFromW alone.
Eigen::Matrix4d rootTransform(const Georef& georef, int up_axis, int up_sign = 1);

/// tileset.json (3D Tiles 1.1): asset, the top-level geometricError (the root box's diagonal:
/// showing nothing is at most that wrong), the root with `transform` (omitted when identity),
/// refine REPLACE on every tile, boxes as the 3D Tiles "box" (centre, half axes), `extras`.
/// Deterministic text (sorted keys, fixed number formatting).
std::string tilesetJson(const TileNode& root, const Eigen::Matrix4d& root_transform,
                        const nlohmann::json& extras);

}  // namespace vdbmap::tiles3d
