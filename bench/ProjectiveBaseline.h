// SPDX-License-Identifier: Apache-2.0
// The baseline of the integration benchmark: a plain projective TSDF on two OpenVDB float
// grids, integrated the way VDBFusion (Vizzo et al. 2022) describes its method: for every
// point, OpenVDB's DDA walks the ray in index space over [range - trunc, range + trunc]; each
// voxel gets the projective distance sign * |p - c| (positive in front of the point), clamped
// above at trunc and skipped below -trunc, with weight 1, through value accessors (running
// average). Single-threaded, fixed truncation, no statistics. Written for this benchmark (not
// their code), so that the target's "VDBFusion ~2 Mpts/s" can be measured as a ratio on the
// same scans, machine and process.
#pragma once

#include <openvdb/math/DDA.h>
#include <openvdb/math/Ray.h>
#include "vdbmap/map/VdbTrees.h"

#include <cmath>
#include <cstddef>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap::bench {

class ProjectiveBaseline {
public:
    ProjectiveBaseline(double voxel_size_m, float trunc_m) : trunc_m_(trunc_m) {
        tsdf_ = openvdb::FloatGrid::create(trunc_m);
        tsdf_->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size_m));
        weight_ = openvdb::FloatGrid::create(0.0f);
        weight_->setTransform(tsdf_->transform().copy());
    }

    /// Returns the number of voxel updates.
    std::size_t integrate(const std::vector<Vec3f>& points_W, const Vec3d& origin_W) {
        using RayT = openvdb::math::Ray<double>;
        auto tsdf = tsdf_->getUnsafeAccessor();
        auto weight = weight_->getUnsafeAccessor();
        const openvdb::math::Transform& xform = tsdf_->transform();
        const double half = 0.5 * xform.voxelSize()[0];
        const openvdb::Vec3d eye(origin_W.x(), origin_W.y(), origin_W.z());
        std::size_t updates = 0;
        for (const Vec3f& pf : points_W) {
            const Vec3d p = pf.cast<double>();
            const Vec3d ray_W = p - origin_W;
            const double range = ray_W.norm();
            if (!(range > trunc_m_)) continue;
            const openvdb::Vec3d dir(ray_W.x() / range, ray_W.y() / range, ray_W.z() / range);
            const RayT ray = RayT(eye, dir, range - trunc_m_, range + trunc_m_).worldToIndex(*tsdf_);
            openvdb::math::DDA<RayT> dda(ray);
            do {
                const openvdb::Coord v = dda.voxel();
                // The corner-indexed voxel's centre, as the DDA's cells are [i, i + 1).
                const openvdb::Vec3d c = xform.indexToWorld(v) + half;
                const Vec3d centre(c.x(), c.y(), c.z());
                const Vec3d to_point = p - centre;
                const double proj = (centre - origin_W).dot(to_point);
                const float sdf = static_cast<float>(std::copysign(to_point.norm(), proj));
                if (sdf <= -trunc_m_) continue;
                const float d = std::min(trunc_m_, sdf);
                const float w_old = weight.getValue(v);
                const float w_new = w_old + 1.0f;
                tsdf.setValue(v, (tsdf.getValue(v) * w_old + d) / w_new);
                weight.setValue(v, w_new);
                ++updates;
            } while (dda.step());
        }
        return updates;
    }

    std::size_t memoryBytes() const {
        return static_cast<std::size_t>(tsdf_->memUsage() + weight_->memUsage());
    }
    openvdb::Index64 activeVoxelCount() const { return tsdf_->activeVoxelCount(); }

    /// visit(ijk, sdf_m, weight) for every updated voxel (to mesh the baseline's map).
    template <typename Visit>
    void forEachVoxel(Visit&& visit) const {
        auto weight = weight_->getConstAccessor();
        for (auto it = tsdf_->cbeginValueOn(); it; ++it) visit(it.getCoord(), *it, weight.getValue(it.getCoord()));
    }

private:
    float trunc_m_;
    openvdb::FloatGrid::Ptr tsdf_;
    openvdb::FloatGrid::Ptr weight_;
};

}  // namespace vdbmap::bench
