// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/sim/LidarModel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <random>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

std::size_t LidarModel::numAzimuths() const {
    return static_cast<std::size_t>(std::lround(360.0 / azimuth_resolution_deg));
}

std::vector<Vec3f> LidarModel::rayDirections() const {
    if (!(azimuth_resolution_deg > 0.0) || elevations_deg.empty()) {
        throw InvalidInput("LidarModel '" + name + "': needs beams and an azimuth resolution > 0");
    }
    const std::size_t n_az = numAzimuths();
    std::vector<Vec3f> dirs;
    dirs.reserve(n_az * elevations_deg.size());
    for (std::size_t a = 0; a < n_az; ++a) {
        const double az = 2.0 * M_PI * static_cast<double>(a) / static_cast<double>(n_az);
        for (double el_deg : elevations_deg) {
            const double el = el_deg * M_PI / 180.0;
            dirs.emplace_back(static_cast<float>(std::cos(el) * std::cos(az)),
                              static_cast<float>(std::cos(el) * std::sin(az)),
                              static_cast<float>(std::sin(el)));
        }
    }
    return dirs;
}

LidarScan simulateScan(const LidarModel& model, const Raycaster& scene, const Isometry3d& T_W_L,
                       std::uint64_t seed) {
    const std::vector<Vec3f> dirs_L = model.rayDirections();
    const Eigen::Matrix3f R_W_L = T_W_L.rotation().cast<float>();
    const Vec3f origin_W = T_W_L.translation().cast<float>();
    std::vector<Vec3f> dirs_W(dirs_L.size());
    for (std::size_t i = 0; i < dirs_L.size(); ++i) dirs_W[i] = R_W_L * dirs_L[i];
    std::vector<std::optional<Raycaster::Hit>> hits;
    scene.intersect({origin_W}, dirs_W, static_cast<float>(model.max_range_m), hits);

    // Noise is drawn sequentially after the parallel cast, so the scan is deterministic.
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, model.range_noise_sigma_m);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    LidarScan scan;
    scan.points_L.points.reserve(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const double n = model.range_noise_sigma_m > 0 ? noise(rng) : 0.0;
        const double drop = uniform(rng);
        if (!hits[i]) continue;
        if (drop < model.dropout_probability) continue;
        const double range = hits[i]->distance + n;
        if (range < model.min_range_m || range > model.max_range_m) continue;
        scan.points_L.points.push_back(dirs_L[i] * static_cast<float>(range));
        // Intensity: Lambertian return, falls with incidence angle.
        const float cos_inc = std::abs(hits[i]->normal_unit.dot(dirs_W[i]));
        scan.points_L.intensity.push_back(0.2f + 0.8f * cos_inc);
        scan.true_points_W.push_back(origin_W + dirs_W[i] * hits[i]->distance);
        scan.faces.push_back(hits[i]->face);
        scan.rays.push_back(static_cast<std::uint32_t>(i));
    }
    return scan;
}

}  // namespace vdbmap
