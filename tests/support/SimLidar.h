// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "vdbmap/core/Types.h"

/// Test helper: a simulated spinning LiDAR ray-casting analytic shapes (plane, sphere,
/// axis-aligned box) in closed form, with deterministic Gaussian range noise. The scene also
/// gives the closed-form signed distance (positive outside / in front), the oracle of the tests.
namespace vdbmap::test {

/// Infinite plane through `point` with unit `normal` (its front side).
struct SimPlane {
    Vec3d point;
    Vec3d normal;
};
struct SimSphere {
    Vec3d centre;
    double radius;
};
struct SimBox {
    Vec3d min;
    Vec3d max;
};

class SimScene {
public:
    void add(const SimPlane& p) { planes_.push_back({p.point, p.normal.normalized()}); }
    void add(const SimSphere& s) { spheres_.push_back(s); }
    void add(const SimBox& b) { boxes_.push_back(b); }

    /// Distance along the unit ray to the first hit (front faces only), or +inf.
    double castRay(const Vec3d& o, const Vec3d& d) const {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& p : planes_) {
            const double den = p.normal.dot(d);
            if (den >= 0.0) continue;  // parallel or seen from behind
            const double t = p.normal.dot(p.point - o) / den;
            if (t > 0.0) best = std::min(best, t);
        }
        for (const auto& s : spheres_) {
            const Vec3d oc = o - s.centre;
            const double b = oc.dot(d);
            const double c = oc.squaredNorm() - s.radius * s.radius;
            const double disc = b * b - c;
            if (disc < 0.0) continue;
            const double t = -b - std::sqrt(disc);
            if (t > 0.0) best = std::min(best, t);
        }
        for (const auto& bx : boxes_) {
            double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
            bool hit = true;
            for (int k = 0; k < 3 && hit; ++k) {
                if (d[k] == 0.0) {
                    if (o[k] < bx.min[k] || o[k] > bx.max[k]) hit = false;
                    continue;
                }
                double ta = (bx.min[k] - o[k]) / d[k], tb = (bx.max[k] - o[k]) / d[k];
                if (ta > tb) std::swap(ta, tb);
                t0 = std::max(t0, ta);
                t1 = std::min(t1, tb);
                if (t0 > t1) hit = false;
            }
            if (hit && t0 > 0.0) best = std::min(best, t0);
        }
        return best;
    }

    /// Closed-form signed distance of the union (min over shapes; exact outside the shapes
    /// and on their surfaces, which is all the tests use).
    double sdf(const Vec3d& x) const {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& p : planes_) best = std::min(best, p.normal.dot(x - p.point));
        for (const auto& s : spheres_) best = std::min(best, (x - s.centre).norm() - s.radius);
        for (const auto& b : boxes_) {
            const Vec3d c = 0.5 * (b.min + b.max), h = 0.5 * (b.max - b.min);
            const Vec3d q = (x - c).cwiseAbs() - h;
            const double outside = q.cwiseMax(0.0).norm();
            const double inside = std::min(q.maxCoeff(), 0.0);
            best = std::min(best, outside + inside);
        }
        return best;
    }

private:
    std::vector<SimPlane> planes_;
    std::vector<SimSphere> spheres_;
    std::vector<SimBox> boxes_;
};

/// A spinning multi-beam LiDAR: `beams` elevations evenly spread over
/// [elevation_min_deg, elevation_max_deg], `azimuth_steps` azimuths over 360 degrees.
struct SimLidarConfig {
    int beams = 64;
    int azimuth_steps = 1024;
    double elevation_min_deg = -24.8;
    double elevation_max_deg = 2.0;
    double max_range_m = 80.0;
    double noise_sigma_m = 0.0;  ///< Gaussian range noise
    std::uint64_t seed = 1;
};

/// Deterministic standard normal from a 64-bit key (splitmix64 + Box-Muller).
inline double gaussianFromKey(std::uint64_t key) {
    auto mix = [](std::uint64_t z) {
        z += 0x9E3779B97F4A7C15ull;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    };
    const std::uint64_t a = mix(key), b = mix(a);
    const double u1 = (static_cast<double>(a >> 11) + 0.5) / 9007199254740992.0;
    const double u2 = (static_cast<double>(b >> 11) + 0.5) / 9007199254740992.0;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

/// One scan from the pose T_W_L: the hit points in the LiDAR frame L. Rays that hit nothing
/// within max_range_m give no point. `scan_index` varies the noise between scans.
inline std::vector<Vec3f> simulateScan(const SimScene& scene, const SimLidarConfig& cfg,
                                       const Isometry3d& T_W_L, std::uint64_t scan_index = 0) {
    std::vector<Vec3f> points_L;
    points_L.reserve(static_cast<std::size_t>(cfg.beams * cfg.azimuth_steps));
    const double deg = 3.141592653589793 / 180.0;
    const Vec3d origin_W = T_W_L.translation();
    for (int b = 0; b < cfg.beams; ++b) {
        const double elev = (cfg.beams == 1)
                                ? cfg.elevation_min_deg * deg
                                : (cfg.elevation_min_deg + (cfg.elevation_max_deg - cfg.elevation_min_deg) *
                                                               b / (cfg.beams - 1)) * deg;
        for (int a = 0; a < cfg.azimuth_steps; ++a) {
            const double az = 2.0 * 3.141592653589793 * a / cfg.azimuth_steps;
            const Vec3d d_L(std::cos(elev) * std::cos(az), std::cos(elev) * std::sin(az), std::sin(elev));
            const Vec3d d_W = T_W_L.linear() * d_L;
            double t = scene.castRay(origin_W, d_W);
            if (!(t <= cfg.max_range_m)) continue;
            if (cfg.noise_sigma_m > 0.0) {
                const std::uint64_t key = (cfg.seed * 0x100000001B3ull) ^ (scan_index << 40) ^
                                          (static_cast<std::uint64_t>(b) << 20) ^ static_cast<std::uint64_t>(a);
                t += cfg.noise_sigma_m * gaussianFromKey(key);
            }
            points_L.push_back((d_L * t).cast<float>());
        }
    }
    return points_L;
}

/// Pose with identity rotation at `position_W`.
inline Isometry3d poseAt(const Vec3d& position_W) {
    Isometry3d T = Isometry3d::Identity();
    T.translation() = position_W;
    return T;
}

}  // namespace vdbmap::test
