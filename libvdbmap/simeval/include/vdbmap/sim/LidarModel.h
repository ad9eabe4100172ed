// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

class Raycaster;

/// A spinning multi-beam LiDAR: one ray per (beam, azimuth step) and revolution.
struct LidarModel {
    std::string name;
    std::vector<double> elevations_deg;  ///< per beam, positive up, in the LiDAR frame
    double azimuth_resolution_deg = 0.2;
    double min_range_m = 1.0;
    double max_range_m = 120.0;
    double range_noise_sigma_m = 0.01;  ///< Gaussian, added along the ray
    double dropout_probability = 0.0;   ///< each return dropped independently

    std::size_t numBeams() const { return elevations_deg.size(); }
    std::size_t numAzimuths() const;
    /// Unit ray directions in the LiDAR frame (x forward, y left, z up), beam-major per azimuth.
    std::vector<Vec3f> rayDirections() const;
};

/// Velodyne HDL-64E preset (KITTI's sensor): 64 beams, +2.0 to -24.33 deg, 0.18 deg azimuth
/// (~10 Hz), 120 m, 2 cm noise, 1 % dropout.
LidarModel hdl64ePreset();
/// Velodyne VLS-128 preset (the paper's sensor): 128 beams, +15 to -25 deg, 0.2 deg azimuth at
/// 10 Hz, 245 m, 1 cm noise, 1 % dropout.
LidarModel vls128Preset();
/// A preset by name ("hdl64", "vls128"); throws ConfigError listing the valid names.
LidarModel lidarPreset(const std::string& name);

/// One simulated scan.
struct LidarScan {
    PointCloud points_L;                 ///< returns in the LiDAR frame, intensity in 0..1
    std::vector<Vec3f> true_points_W;    ///< the noise-free surface points of the returns
    std::vector<std::uint32_t> faces;    ///< the hit triangle of each return
    std::vector<std::uint32_t> rays;     ///< index of each return's ray in rayDirections()
};

/// Casts every ray of `model` from pose `T_W_L` against `scene` (parallel), adds Gaussian range
/// noise and dropout from a generator seeded with `seed` (deterministic for a seed, whatever
/// the thread count). Returns with range outside [min_range_m, max_range_m] are dropped.
LidarScan simulateScan(const LidarModel& model, const Raycaster& scene, const Isometry3d& T_W_L,
                       std::uint64_t seed);

}  // namespace vdbmap
