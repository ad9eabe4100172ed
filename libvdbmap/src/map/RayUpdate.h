// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/Types.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "map/FastReciprocal.h"
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

/// One axis of the Amanatides-Woo walk of integrateRay: the voxel index along it and what a
/// step along it adds to the ray parameter, the sdf, t and the offset in the leaf.
struct WalkAxis {
    int ijk = 0;
    int step = 0;         ///< +1, -1 or 0 (the ray is parallel to the axis)
    int d_offset = 0;     ///< step * stride of the axis in LeafNode<.., 3>::coordToOffset
    int entry_local = 0;  ///< the local coordinate (0 or 7) at which a step enters a new leaf
    float t_max = 0.0f;   ///< ray parameter (voxels) of the next crossing of this axis
    float t_delta = 0.0f;
    float d_sdf = 0.0f;  ///< step * normal * voxel
    float d_t = 0.0f;    ///< step * dir * voxel

    WalkAxis(float start_idx, float dir, float normal, float voxel_m, int stride) {
        constexpr float kInf = std::numeric_limits<float>::infinity();
        ijk = floorToInt(start_idx);
        if (dir > 0.0f) {
            step = 1;
            t_delta = 1.0f / dir;
            t_max = (static_cast<float>(ijk) + 1.0f - start_idx) * t_delta;
        } else if (dir < 0.0f) {
            step = -1;
            t_delta = -1.0f / dir;
            t_max = (start_idx - static_cast<float>(ijk)) * t_delta;
        } else {
            t_delta = kInf;
            t_max = kInf;
        }
        d_sdf = static_cast<float>(step) * normal * voxel_m;
        d_t = static_cast<float>(step) * dir * voxel_m;
        d_offset = step * stride;
        entry_local = step > 0 ? 0 : 7;
    }
};

/// The voxel updates of one measurement point (paper Sec. 4.2). Every voxel v pierced by the
/// segment (Amanatides-Woo order along the ray) gets
///   sdf = n . (c_v - p), clamped to [-eps, eps]    (c_v: voxel centre, n: block normal)
///   w   = RayWeight: w_inc * distanceFalloff(t) * f(sdf), f = 1 for sdf >= -voxel, then
///         linear to 0 at -eps (behindSurfaceFactor), t = (c_v - p) . dir
/// The sink is told the 8^3 leaf the walk is in, `enterLeaf(origin)` (false: no such leaf, its
/// voxels are skipped), and gets `update(i, j, k, offset_in_leaf, sdf_m, w)` for every voxel
/// with w > 0. The sdf, t, the offset in the leaf and the leaf crossings are carried
/// incrementally along the walk: float arithmetic, no division per voxel (FastReciprocal.h). The
/// three axes are separate objects and the step is a branch per axis, so that the walk's state
/// stays in registers (no array indexed by the stepping axis). Returns the number of updates.
template <typename Sink>
inline std::size_t integrateRay(const RaySegment& seg, const Vec3f& p_W, const Vec3f& dir_W,
                                const Vec3f& normal_W, float eps_m, float voxel_m,
                                const RayWeight& weight, Sink& sink) {
    WalkAxis ax(seg.start_idx.x(), dir_W.x(), normal_W.x(), voxel_m, 64);
    WalkAxis ay(seg.start_idx.y(), dir_W.y(), normal_W.y(), voxel_m, 8);
    WalkAxis az(seg.start_idx.z(), dir_W.z(), normal_W.z(), voxel_m, 1);
    const Vec3f c0_minus_p(static_cast<float>(ax.ijk) * voxel_m - p_W.x(),
                           static_cast<float>(ay.ijk) * voxel_m - p_W.y(),
                           static_cast<float>(az.ijk) * voxel_m - p_W.z());
    float sdf = normal_W.x() * c0_minus_p.x() + normal_W.y() * c0_minus_p.y() +
                normal_W.z() * c0_minus_p.z();
    float t = dir_W.x() * c0_minus_p.x() + dir_W.y() * c0_minus_p.y() + dir_W.z() * c0_minus_p.z();
    auto offsetOf = [&]() {
        return static_cast<unsigned>(((ax.ijk & 7) << 6) | ((ay.ijk & 7) << 3) | (az.ijk & 7));
    };
    auto originOf = [&]() { return openvdb::Coord(ax.ijk & ~7, ay.ijk & ~7, az.ijk & ~7); };
    unsigned offset = offsetOf();
    bool in_leaf = sink.enterLeaf(originOf());
    const float length_idx = seg.length_idx;
    const float w_inc = weight.w_inc, inv_falloff2 = weight.inv_falloff2,
                falloff_floor = weight.falloff_floor, inv_dropoff = weight.inv_dropoff;
    // One step along axis a; false at the end of the segment.
    auto advance = [&](WalkAxis& a) {
        if (a.t_max > length_idx) return false;
        a.ijk += a.step;
        a.t_max += a.t_delta;
        sdf += a.d_sdf;
        t += a.d_t;
        // Stepping forward into local coordinate 0, or backward into 7, enters a new leaf.
        if ((a.ijk & 7) == a.entry_local) {
            offset = offsetOf();
            in_leaf = sink.enterLeaf(originOf());
        } else {
            offset = static_cast<unsigned>(static_cast<int>(offset) + a.d_offset);
        }
        return true;
    };
    std::size_t updates = 0;
    // A segment of length L crosses at most L * sqrt(3) + 3 voxel faces.
    const int max_steps = static_cast<int>(length_idx * 1.7320508f + 4.0f);
    for (int s = 0; s < max_steps; ++s) {
        const float d = sdf > eps_m ? eps_m : (sdf < -eps_m ? -eps_m : sdf);
        const float falloff = distanceFalloff(t, inv_falloff2, falloff_floor,
                                              [](float x) { return reciprocalEstimate(x); });
        const float w = w_inc * falloff * behindSurfaceFactor(d, eps_m, voxel_m, inv_dropoff);
        if (in_leaf && w > 0.0f) {
            sink.update(ax.ijk, ay.ijk, az.ijk, offset, d, w);
            ++updates;
        }
        const bool more = ax.t_max < ay.t_max ? (ax.t_max < az.t_max ? advance(ax) : advance(az))
                                              : (ay.t_max < az.t_max ? advance(ay) : advance(az));
        if (!more) break;
    }
    return updates;
}

}  // namespace vdbmap::detail
