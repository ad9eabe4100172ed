// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/sim/SimScene.h"

namespace vdbmap {

/// Procedural 256x256 BGR textures per surface kind ("asphalt", "lane", "sidewalk", "curb",
/// "brick", "glass", "metal", "sign", "foliage", "bark", "car_red", "car_blue", "car_silver",
/// "tyre", "grass", "suv", "window", "skin"; the traffic's "car_yellow", "car_green",
/// "car_orange", "van_white", "shirt_purple", "shirt_cyan", "trousers"), deterministic for a seed. Throws InvalidInput
/// for an unknown kind.
cv::Mat proceduralTexture(const std::string& kind, std::uint64_t seed);

/// A simulated scene and the vehicle trajectory through it (scene frame S: z up).
struct SceneSetup {
    SimScene scene;
    std::vector<Isometry3d> T_S_V;  ///< vehicle pose per frame (x forward, y left, z up)
    double lidar_height_m = 1.73;   ///< LiDAR above the vehicle origin (on the ground)
    double frame_rate_hz = 10.0;
    /// Where moving occluders may appear (per frame, in front of the vehicle), in metres.
    double occluder_ahead_m = 8.0;
};

/// Options of the `street` scene.
struct StreetSceneOptions {
    double length_m = 60.0;    ///< length of the street (x in S)
    std::size_t frames = 20;   ///< vehicle poses, evenly along the road
    std::uint64_t seed = 1;
    /// Folder with spot_triangulated.obj + spot_texture.png (class 20 "other object" on the
    /// sidewalk); empty = no Spot.
    std::filesystem::path spot_dir;
};

/// Street: two-lane road (class 0) with dashed/solid lane markings and arrows (19), kerbs and
/// sidewalks (1), buildings with recessed windows (2), poles (5) with signs (7), trees and
/// bushes (8), parked cars (13) and the Spot mesh (20). The vehicle drives along the right lane.
SceneSetup buildStreetScene(const StreetSceneOptions& options);

/// Options of the `suv` scene (the paper's LGSVL experiment).
struct SuvSceneOptions {
    std::size_t frames = 126;     ///< 10 Hz at 5 m/s on a 10 m circle: 126 frames = one lap
    double circle_radius_m = 10.0;
    double speed_mps = 5.0;
    std::uint64_t seed = 1;
};

/// SUV: a car-sized SUV (body, cabin, bumpers, four wheels; class 13) on a flat ground plane
/// (class 0); the vehicle circles it counter-clockwise, LiDAR 2.3 m above the ground.
SceneSetup buildSuvScene(const SuvSceneOptions& options);

}  // namespace vdbmap
