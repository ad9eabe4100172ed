// SPDX-License-Identifier: Apache-2.0
// The peer of the speed target, VDBFusion (Vizzo et al. 2022), as its `VDBVolume::Integrate`
// does the work, operation for operation, written for this benchmark (not their code):
//   - the scan arrives as std::vector<Eigen::Vector3d> (as their C++ and Python APIs take it;
//     the conversion is done beforehand, like the reading);
//   - per point: the direction normalised as an openvdb::Vec3R, the depth as a float, and a
//     float ray (openvdb::math::Ray<float>) over [depth - trunc, depth + trunc] taken to index
//     space and walked by openvdb::math::DDA;
//   - per voxel: the centre indexToWorld(v) + voxel / 2 as an Eigen::Vector3d (the voxel size
//     asked of the transform each time, a float), the sdf
//     sign * |p - c| with sign = proj / |proj| (a division, as they write it), skipped unless
//     sdf > -trunc, the weight from a std::function<float(float)> (their pipelines pass a
//     constant 1), and the running average through unsafe accessors of the tsdf and weight
//     float grids (the colour grid's accessor is made, no colours are given).
// ProjectiveBaseline.h is the leaner variant written first (float points, double ray,
// std::copysign, no weighting call); the benchmark runs both and reports both.
#pragma once

#include <openvdb/math/DDA.h>
#include <openvdb/math/Ray.h>
#include "vdbmap/map/VdbTrees.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

namespace vdbmap::bench {

class VdbFusionBaseline {
public:
    VdbFusionBaseline(double voxel_size_m, float sdf_trunc_m)
        : voxel_size_m_(static_cast<float>(voxel_size_m)), sdf_trunc_m_(sdf_trunc_m) {
        tsdf_ = openvdb::FloatGrid::create(sdf_trunc_m_);
        tsdf_->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size_m_));
        tsdf_->setGridClass(openvdb::GRID_LEVEL_SET);
        weights_ = openvdb::FloatGrid::create(0.0f);
        weights_->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size_m_));
        colors_ = openvdb::Vec3SGrid::create(openvdb::Vec3f(0.0f, 0.0f, 0.0f));
        colors_->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size_m_));
    }

    /// Returns the number of voxel updates.
    std::size_t integrate(const std::vector<Eigen::Vector3d>& points_W, const Eigen::Vector3d& origin_W,
                          const std::function<float(float)>& weighting_function) {
        const openvdb::math::Transform& xform = tsdf_->transform();
        const openvdb::Vec3R eye(origin_W.x(), origin_W.y(), origin_W.z());
        auto tsdf_acc = tsdf_->getUnsafeAccessor();
        auto weights_acc = weights_->getUnsafeAccessor();
        auto colors_acc = colors_->getUnsafeAccessor();
        (void)colors_acc;
        std::size_t updates = 0;
        for (std::size_t i = 0; i < points_W.size(); ++i) {
            const Eigen::Vector3d point = points_W[i];
            const Eigen::Vector3d direction = point - origin_W;
            openvdb::Vec3R dir(direction.x(), direction.y(), direction.z());
            dir.normalize();
            const auto depth = static_cast<float>(direction.norm());
            const float t0 = depth - sdf_trunc_m_;
            const float t1 = depth + sdf_trunc_m_;
            const auto ray = openvdb::math::Ray<float>(eye, dir, t0, t1).worldToIndex(*tsdf_);
            openvdb::math::DDA<decltype(ray)> dda(ray);
            do {
                const openvdb::Coord voxel = dda.voxel();
                const Eigen::Vector3d centre = voxelCentre(voxel, xform);
                const float sdf = signedDistance(origin_W, point, centre);
                if (sdf > -sdf_trunc_m_) {
                    const float tsdf = std::min(sdf_trunc_m_, sdf);
                    const float weight = weighting_function(sdf);
                    const float last_weight = weights_acc.getValue(voxel);
                    const float last_tsdf = tsdf_acc.getValue(voxel);
                    const float new_weight = weight + last_weight;
                    tsdf_acc.setValue(voxel, (last_tsdf * last_weight + tsdf * weight) / new_weight);
                    weights_acc.setValue(voxel, new_weight);
                    ++updates;
                }
            } while (dda.step());
        }
        return updates;
    }

private:
    /// As their GetVoxelCenter: the voxel size is asked of the transform for every voxel.
    static Eigen::Vector3d voxelCentre(const openvdb::Coord& voxel, const openvdb::math::Transform& xform) {
        const float voxel_size = static_cast<float>(xform.voxelSize()[0]);
        const openvdb::Vec3d c = xform.indexToWorld(voxel) + voxel_size / 2.0;
        return Eigen::Vector3d(c.x(), c.y(), c.z());
    }

    static float signedDistance(const Eigen::Vector3d& origin, const Eigen::Vector3d& point,
                                const Eigen::Vector3d& centre) {
        const Eigen::Vector3d centre_from_origin = centre - origin;
        const Eigen::Vector3d point_from_centre = point - centre;
        const double dist = point_from_centre.norm();
        const double proj = centre_from_origin.dot(point_from_centre);
        const double sign = proj / std::abs(proj);
        return static_cast<float>(sign * dist);
    }

    float voxel_size_m_;
    float sdf_trunc_m_;
    openvdb::FloatGrid::Ptr tsdf_;
    openvdb::FloatGrid::Ptr weights_;
    openvdb::Vec3SGrid::Ptr colors_;
};

}  // namespace vdbmap::bench
