// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/math/Coord.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "map/RayTraversal.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/BlockStats.h"
#include "vdbmap/map/MeasurementWeight.h"
#include "vdbmap/map/RingSpacing.h"
#include "vdbmap/map/Truncation.h"

namespace vdbmap::test {

/// A slow, serial reference of AtsdfIntegrator (paper Sec. 4), written to be read: ordered
/// maps, double arithmetic, one block and one point after another, no packing, no leaves, no
/// colouring. The oracle of tests/unit/ReferenceIntegratorTest.cpp.
class ReferenceIntegrator {
public:
    struct Voxel {
        double sdf = 0.0, weight = 0.0;
    };
    struct Block {
        BlockStats stats;
        PlaneEstimate plane;
        double eps = 0.0;
    };

    ReferenceIntegrator(double voxel_m, const AtsdfConfig& config)
        : vs_(voxel_m), c_(resolveAtsdfConfig(config, voxel_m)) {}

    void integrateScan(const std::vector<Vec3f>& points_L, const Isometry3d& T_W_L) {
        const Vec3d sensor = T_W_L.translation();
        // 1. The valid points of each block, in scan order (the world points in float, as the
        //    integrator transforms them).
        const Eigen::Isometry3f T = T_W_L.cast<float>();
        // The scan's rings, for the band behind grazing points (grazing_band_to_next_ring).
        use_rings_ = c_.truncation.mode == TruncationMode::Adaptive && c_.truncation.grazing_band_to_next_ring;
        if (use_rings_) {
            rings_ = RingSpacing::estimate(points_L);
            use_rings_ = rings_.valid();
            up_W_ = T_W_L.linear() * Vec3d::UnitZ();
        }
        std::map<openvdb::Coord, std::vector<Vec3d>> scan;
        for (const Vec3f& p_L : points_L) {
            const Vec3f p = T * p_L;
            if (!p.allFinite()) continue;
            const double range = (p.cast<double>() - sensor).norm();
            if (range < c_.min_range_m || range > c_.max_range_m) continue;
            scan[blockOf(p)].push_back(p.cast<double>());
        }
        // 2. Eq. (1) merge, plane (Eq. 2, 3) and eps (Eq. 4) of every block of the scan.
        for (const auto& [key, pts] : scan) {
            Block& b = blocks_[key];
            b.stats = mergeStats(b.stats, batchStats(pts));
            b.plane = estimatePlane(b.stats, sensor, c_.min_points_for_pca,
                                    std::max(0.25 * vs_, 2.0 * c_.range_noise_m));
            b.eps = truncationFor(c_.truncation, b.plane, b.stats.n);
        }
        // 3. Every point updates the voxels its segment pierces.
        for (const auto& [key, pts] : scan) {
            const Block& b = blocks_[key];
            double flatness = 0.0;
            const Vec3d normal = normalOf(key, sensor, flatness);
            // Each point, or (merge_divisions s) the mean of the points of each cell (voxel / s)
            // weighted by their count, cells in the order their first point comes.
            for (const auto& [p, count] : c_.merge_divisions > 0 ? perCell(pts) : perPoint(pts))
                updateAlongRay(p, sensor, normal, flatness, b.eps, count);
        }
    }

    const std::map<openvdb::Coord, Voxel>& voxels() const { return voxels_; }

private:
    using Rays = std::vector<std::pair<Vec3d, double>>;  ///< point, points it stands for

    static Rays perPoint(const std::vector<Vec3d>& pts) {
        Rays rays;
        for (const Vec3d& p : pts) rays.emplace_back(p, 1.0);
        return rays;
    }

    Rays perCell(const std::vector<Vec3d>& pts) const {
        std::map<openvdb::Coord, std::size_t> ray_of_cell;
        std::vector<Vec3d> sum;  // of the offsets from the cell's first point
        Rays rays;
        for (const Vec3d& p : pts) {
            const auto [it, first] =
                ray_of_cell.emplace(cellOf(p.cast<float>(), c_.merge_divisions), rays.size());
            if (first) {
                rays.emplace_back(p, 1.0);
                sum.push_back(Vec3d::Zero());
            } else {
                sum[it->second] += p - rays[it->second].first;
                rays[it->second].second += 1.0;
            }
        }
        for (std::size_t i = 0; i < rays.size(); ++i) rays[i].first += sum[i] / rays[i].second;
        return rays;
    }

    /// The cell of a point: floor((p / voxel + 1/2) s), in float as the integrator; s = 1: its
    /// voxel (voxel i covers [i - 1/2, i + 1/2)).
    openvdb::Coord cellOf(const Vec3f& p, int divisions) const {
        const float s = static_cast<float>(divisions);
        const float inv = static_cast<float>(1.0 / vs_);
        return openvdb::Coord(static_cast<int>(std::floor((p.x() * inv + 0.5f) * s)),
                              static_cast<int>(std::floor((p.y() * inv + 0.5f) * s)),
                              static_cast<int>(std::floor((p.z() * inv + 0.5f) * s)));
    }

    /// The 8^3 block of a point's voxel.
    openvdb::Coord blockOf(const Vec3f& p) const {
        const openvdb::Coord v = cellOf(p, 1);
        return openvdb::Coord(v.x() >> 3, v.y() >> 3, v.z() >> 3);
    }

    /// The block's own normal; a degenerate block's: the n-weighted mean of its 26 neighbours'
    /// valid normals, each turned towards the sensor; none: zero (the ray direction is used).
    /// `flatness`: P_flat of the block's plane, or the n-weighted mean of the neighbours'.
    Vec3d normalOf(const openvdb::Coord& key, const Vec3d& sensor, double& flatness) const {
        const Block& b = blocks_.at(key);
        if (b.plane.valid) {
            flatness = b.plane.flatness;
            return b.plane.normal;
        }
        Vec3d sum = Vec3d::Zero();
        double flat_sum = 0.0, n_sum = 0.0;
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = blocks_.find(key.offsetBy(dx, dy, dz));
                    if (it == blocks_.end() || !it->second.plane.valid) continue;
                    Vec3d n = it->second.plane.normal;
                    if (n.dot(sensor - it->second.stats.mean) < 0.0) n = -n;
                    sum += it->second.stats.n * n;
                    flat_sum += it->second.stats.n * it->second.plane.flatness;
                    n_sum += it->second.stats.n;
                }
        flatness = n_sum > 0.0 ? flat_sum / n_sum : 0.0;
        return sum.norm() > 0.0 ? Vec3d(sum.normalized()) : Vec3d::Zero();
    }

    /// The point q on the surface lies in a block with points whose plane passes within b of
    /// q: its own (with a normal within ~25 deg of n) or, without one, n's through the mean of
    /// its points (the integrator's landsOnPlane).
    bool landsOnPlane(const Vec3d& q, const Vec3d& n) const {
        const auto it = blocks_.find(blockOf(q.cast<float>()));
        if (it == blocks_.end() || it->second.stats.n <= 0.0) return false;
        const bool valid = it->second.plane.valid;
        const Vec3d& m = valid ? it->second.plane.normal : n;
        if (valid && std::abs(m.dot(n)) < 0.9) return false;
        return std::abs(m.dot(q - it->second.stats.mean)) <= c_.truncation.grazing_band_m;
    }

    /// `count`: the points the ray stands for (its weight's factor).
    void updateAlongRay(const Vec3d& p, const Vec3d& sensor, const Vec3d& block_normal,
                        double flatness, double eps, double count) {
        const Vec3d dir = (p - sensor).normalized();
        const bool has_normal = block_normal.squaredNorm() > 0.0;
        const Vec3d n = has_normal ? block_normal : Vec3d(-dir);
        // Paper mode: the paper's incidence weight; adaptive and fixed: the noise weight of the
        // sample's distance along the normal, times the falloff with the distance along the ray.
        const bool paper = c_.truncation.mode == TruncationMode::Paper;
        const double w_inc = count * (paper ? (has_normal ? incidenceWeight(n, sensor, p, c_.weight_floor) : 1.0)
                                            : noiseWeight(std::abs(n.dot(dir)), blockNoiseRatio(c_.noise_ratio, flatness)));
        const double inv_l2 = !paper && c_.falloff_m > 0.0 ? 1.0 / (c_.falloff_m * c_.falloff_m) : 0.0;
        // Without a normal (isolated degenerate block) the band is [-eps, eps] along the ray.
        RayBand band = has_normal ? rayBandFor(c_.truncation, eps, std::abs(n.dot(dir))) : RayBand{eps, eps};
        if (has_normal && use_rings_) {  // to the next ring, if it lands on this surface
            const double gap = rings_.surfaceGap(dir, n, up_W_, (p - sensor).norm());
            const RayBand to_ring = rayBandFor(c_.truncation, eps, std::abs(n.dot(dir)), gap);
            if (to_ring.back_m > band.back_m && landsOnPlane(p + to_ring.back_m * (dir - n.dot(dir) * n), n))
                band = to_ring;
        }
        // A merged ray's band starts further in front (mergedRayFrontExtension).
        if (count > 1.0) band.front_m += mergedRayFrontExtension(c_, vs_);
        detail::traverseSegment(p - band.front_m * dir, dir, band.front_m + band.back_m, 1.0 / vs_,
                                [&](const openvdb::Coord& v) {
            const Vec3d centre(v.x() * vs_, v.y() * vs_, v.z() * vs_);
            const double sdf = std::clamp(n.dot(centre - p), -eps, eps);
            const double t = dir.dot(centre - p);
            const double w = w_inc * distanceFalloff(t, inv_l2, c_.weight_floor) *
                             behindSurfaceFactor(sdf, eps, vs_);
            if (!(w > 0.0)) return;
            Voxel& x = voxels_[v];
            x.sdf = (x.weight * x.sdf + w * sdf) / (x.weight + w);
            x.weight = std::min(x.weight + w, c_.max_weight);
        });
    }

    double vs_;
    AtsdfConfig c_;
    std::map<openvdb::Coord, Block> blocks_;
    std::map<openvdb::Coord, Voxel> voxels_;
    bool use_rings_ = false;
    RingSpacing rings_;
    Vec3d up_W_ = Vec3d::UnitZ();
};

}  // namespace vdbmap::test
