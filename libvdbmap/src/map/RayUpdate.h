// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/math/Coord.h>

#include <cstdint>
#include <limits>

#include "vdbmap/core/Types.h"
#include "vdbmap/map/MeasurementWeight.h"

namespace vdbmap::detail {

/// floor() for |x| < 2^31 without a libm call (baseline x86-64 has no roundss).
inline int floorToInt(float x) {
    const int i = static_cast<int>(x);
    return i - (x < static_cast<float>(i) ? 1 : 0);
}

/// Voxel index of a world point: voxel (i,j,k) covers [i-0.5, i+0.5) * voxel size.
inline openvdb::Coord voxelOf(const Vec3f& p_W, float inv_voxel) {
    return openvdb::Coord(floorToInt(p_W.x() * inv_voxel + 0.5f), floorToInt(p_W.y() * inv_voxel + 0.5f),
                          floorToInt(p_W.z() * inv_voxel + 0.5f));
}

/// The update segment of one measurement point p along its unit ray direction: t in
/// [0, 2 eps] from p - eps dir, in index space (voxel i covers [i - 0.5, i + 0.5) voxels, so
/// the cell of x is floor(x / voxel + 0.5)). Phase 2 (leaf allocation) and phase 3 (the voxel
/// updates) of the integrator both derive the segment from this one expression.
struct RaySegment {
    Vec3f start_idx;  ///< (p - eps dir) / voxel + 0.5
    float length_idx;  ///< 2 eps / voxel

    static RaySegment of(const Vec3f& p_W, const Vec3f& dir_W, float eps_m, float inv_voxel) {
        return {(p_W - eps_m * dir_W) * inv_voxel + Vec3f::Constant(0.5f), 2.0f * eps_m * inv_voxel};
    }
    /// t in [-front_m, back_m] around p (front: towards the sensor).
    static RaySegment of(const Vec3f& p_W, const Vec3f& dir_W, float front_m, float back_m,
                         float inv_voxel) {
        return {(p_W - front_m * dir_W) * inv_voxel + Vec3f::Constant(0.5f),
                (front_m + back_m) * inv_voxel};
    }
    openvdb::Coord startVoxel() const {
        return openvdb::Coord(floorToInt(start_idx.x()), floorToInt(start_idx.y()),
                              floorToInt(start_idx.z()));
    }
    /// The voxel of the end point, pushed out by 1e-4 voxel so that the DDA's rounding cannot
    /// end beyond it (the leaves between start and end voxel are allocated).
    openvdb::Coord endVoxel(const Vec3f& dir_W) const {
        const Vec3f e = start_idx + (length_idx + 1e-4f) * dir_W;
        return openvdb::Coord(floorToInt(e.x()), floorToInt(e.y()), floorToInt(e.z()));
    }
};

/// The weight of one point's voxel updates:
///   w = w_inc * distanceFalloff(t) * behindSurfaceFactor(sdf)   (vdbmap/map/MeasurementWeight.h)
/// with t the voxel's distance along the ray from the point.
struct RayWeight {
    float w_inc = 1.0f;          ///< per point: noiseWeight (adaptive, fixed) or the incidence weight (paper)
    float inv_dropoff = 0.0f;    ///< 1 / (eps - voxel), 0 when eps <= voxel (no drop-off)
    float inv_falloff2 = 0.0f;   ///< 1 / l^2 of distanceFalloff, 0 = none (paper mode)
    float falloff_floor = 1.0f;  ///< distanceFalloff's floor
};

/// The voxel updates of one measurement point (paper Sec. 4.2). Every voxel v pierced by the
/// segment (Amanatides-Woo order along the ray) gets
///   sdf = n . (c_v - p), clamped to [-eps, eps]    (c_v: voxel centre, n: block normal)
///   w   = RayWeight: w_inc * distanceFalloff(t) * f(sdf), f = 1 for sdf >= -voxel, then
///         linear to 0 at -eps (behindSurfaceFactor), t = (c_v - p) . dir
/// The sink is told the 8^3 leaf the walk is in, `enterLeaf(origin)` (false: no such leaf, its
/// voxels are skipped), and gets `update(ijk, offset_in_leaf, sdf_m, w)` for every voxel with
/// w > 0. The sdf, t, the offset in the leaf and the leaf crossings are carried incrementally
/// along the walk: float arithmetic, one division per voxel (the falloff).
template <typename Sink>
inline void integrateRay(const RaySegment& seg, const Vec3f& p_W, const Vec3f& dir_W,
                         const Vec3f& normal_W, float eps_m, float voxel_m, const RayWeight& weight,
                         Sink& sink) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr int kStride[3] = {64, 8, 1};  // LeafNode<.., 3>::coordToOffset
    int ijk[3];
    int step[3];
    int d_offset[3];
    float t_max[3];
    float t_delta[3];
    float d_sdf[3];
    float d_t[3];
    for (int k = 0; k < 3; ++k) {
        const float a = seg.start_idx[k];
        const int fl = floorToInt(a);
        ijk[k] = fl;
        const float d = dir_W[k];
        if (d > 0.0f) {
            step[k] = 1;
            t_delta[k] = 1.0f / d;
            t_max[k] = (static_cast<float>(fl) + 1.0f - a) * t_delta[k];
        } else if (d < 0.0f) {
            step[k] = -1;
            t_delta[k] = -1.0f / d;
            t_max[k] = (a - static_cast<float>(fl)) * t_delta[k];
        } else {
            step[k] = 0;
            t_delta[k] = kInf;
            t_max[k] = kInf;
        }
        d_sdf[k] = static_cast<float>(step[k]) * normal_W[k] * voxel_m;
        d_t[k] = static_cast<float>(step[k]) * dir_W[k] * voxel_m;
        d_offset[k] = step[k] * kStride[k];
    }
    float sdf = normal_W.x() * (static_cast<float>(ijk[0]) * voxel_m - p_W.x()) +
                normal_W.y() * (static_cast<float>(ijk[1]) * voxel_m - p_W.y()) +
                normal_W.z() * (static_cast<float>(ijk[2]) * voxel_m - p_W.z());
    float t = dir_W.x() * (static_cast<float>(ijk[0]) * voxel_m - p_W.x()) +
              dir_W.y() * (static_cast<float>(ijk[1]) * voxel_m - p_W.y()) +
              dir_W.z() * (static_cast<float>(ijk[2]) * voxel_m - p_W.z());
    auto offsetOf = [&]() {
        return static_cast<unsigned>(((ijk[0] & 7) << 6) | ((ijk[1] & 7) << 3) | (ijk[2] & 7));
    };
    auto originOf = [&]() { return openvdb::Coord(ijk[0] & ~7, ijk[1] & ~7, ijk[2] & ~7); };
    unsigned offset = offsetOf();
    bool in_leaf = sink.enterLeaf(originOf());
    // A segment of length L crosses at most L * sqrt(3) + 3 voxel faces.
    const int max_steps = static_cast<int>(seg.length_idx * 1.7320508f + 4.0f);
    for (int s = 0; s < max_steps; ++s) {
        const float d = sdf > eps_m ? eps_m : (sdf < -eps_m ? -eps_m : sdf);
        const float w = weight.w_inc *
                        distanceFalloff(t, weight.inv_falloff2, weight.falloff_floor) *
                        behindSurfaceFactor(d, eps_m, voxel_m, weight.inv_dropoff);
        if (in_leaf && w > 0.0f) sink.update(ijk, offset, d, w);
        const int axis = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2)
                                             : (t_max[1] < t_max[2] ? 1 : 2);
        if (t_max[axis] > seg.length_idx) break;
        ijk[axis] += step[axis];
        t_max[axis] += t_delta[axis];
        sdf += d_sdf[axis];
        t += d_t[axis];
        // Stepping forward into local coordinate 0, or backward into 7, enters a new leaf.
        const int local = ijk[axis] & 7;
        if (local == (step[axis] > 0 ? 0 : 7)) {
            offset = offsetOf();
            in_leaf = sink.enterLeaf(originOf());
        } else {
            offset = static_cast<unsigned>(static_cast<int>(offset) + d_offset[axis]);
        }
    }
}

}  // namespace vdbmap::detail
