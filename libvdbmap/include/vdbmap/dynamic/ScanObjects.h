// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// How one scan is cut into objects for the object-level decision (docs/dynamic.md, "Objects").
struct ScanObjectConfig {
    bool enabled = true;
    /// Ground: per cell of ground_cell_m in the sensor's xy plane the lowest point; the ground
    /// height of a cell is the least over the cells within ground_radius_cells of
    /// (their lowest z + ground_slope * horizontal distance). Points less than ground_band_m
    /// above it are ground and join no object (ERASOR and Dynablox keep the ground this way).
    double ground_cell_m = 1.0;
    int ground_radius_cells = 2;
    double ground_slope = 0.1;
    double ground_band_m = 0.2;
    /// Points of the ground band higher than this above the ground height and under a moving
    /// object's footprint (grown by voxel_m) go with the object: a car's wheels and underside.
    double low_band_min_m = 0.05;
    /// Objects: connected components of the non-ground points over voxels of this size
    /// (26-neighbourhood).
    double voxel_m = 0.2;
    /// An object is moving when at least min_points of its points and at least min_fraction of
    /// them were found moving by the free-space test, and its horizontal extent is at most
    /// max_extent_m (a facade with a few wrong points never is).
    int min_points = 5;
    double min_fraction = 0.2;
    double max_extent_m = 20.0;
};

/// One object (cluster) of a scan.
struct ScanCluster {
    Vec3d centroid_W = Vec3d::Zero();  ///< world frame W, metres
    Vec3f min_L = Vec3f::Zero(), max_L = Vec3f::Zero();  ///< bounding box in the sensor frame L
    Vec3d min_W = Vec3d::Zero(), max_W = Vec3d::Zero();  ///< bounding box in the world frame W
    std::uint32_t points = 0;
    std::uint32_t dynamic_points = 0;  ///< found moving by the free-space test
    /// Static by evidence: a scan hit them and none saw through them (DynamicDetector fills it
    /// from the free-space votes; ObjectTrackConfig::static_share).
    std::uint32_t static_points = 0;
    bool confirmed = false;            ///< moving by its own points (ScanObjectConfig)
    bool compact = false;              ///< horizontal extent within max_extent_m
    float extent_m = 0.0f;             ///< horizontal diagonal of the L bounding box
};

/// The objects of one scan.
struct ScanObjects {
    static constexpr std::int32_t kGround = -1;  ///< below the ground band's low part
    static constexpr std::int32_t kLow = -2;     ///< in the ground band, above low_band_min_m
    /// Per point: its cluster's index, or kGround / kLow.
    std::vector<std::int32_t> cluster;
    std::vector<ScanCluster> clusters;
};

/// Cuts the scan `points_L` (sensor frame L, z up, pose T_W_L) into ground and objects and
/// counts in each object the points flagged in `dynamic` (the free-space test). Deterministic
/// (sequential; clusters numbered by their first point in scan order).
ScanObjects findScanObjects(const std::vector<Vec3f>& points_L, const std::vector<std::uint8_t>& dynamic,
                            const Isometry3d& T_W_L, const ScanObjectConfig& config);

/// Points of the ground band (kLow) under the footprint of a cluster flagged in `moving`, the
/// footprint being its L bounding box in x and y grown by `grow_m`: 1 for those, else 0.
std::vector<std::uint8_t> lowPointsUnder(const std::vector<Vec3f>& points_L, const ScanObjects& objects,
                                         const std::vector<std::uint8_t>& moving, float grow_m);

/// Points of objects not flagged in `moving`, not themselves `dynamic`, within `rings` voxels of
/// `voxel_m` (26-neighbourhood, in L) of a voxel holding at least `min_seed_points` points
/// flagged in `dynamic`, or below such a voxel by up to `down` more voxels (within `rings`
/// horizontally: the legs under a pedestrian's moving body): 1 for those, else 0.
std::vector<std::uint8_t> pointsNearDynamic(const std::vector<Vec3f>& points_L,
                                            const std::vector<std::uint8_t>& dynamic,
                                            const ScanObjects& objects,
                                            const std::vector<std::uint8_t>& moving, float voxel_m,
                                            int rings, int min_seed_points, int down = 0);

}  // namespace vdbmap
