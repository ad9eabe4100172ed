// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "map/RayUpdate.h"
#include "vdbmap/core/Types.h"

namespace vdbmap::detail {

/// Why phase 1 drops a point; 0 keeps it. The values index the integrator's drop counts (+1).
enum PointStatus : std::int32_t { kValid = 0, kNonFinite = 1, kAtOrigin = 2, kRange = 3 };

/// What phase 1 checks a point against: squared range bounds around the sensor origin, and the
/// largest |coordinate| / voxel: points further from the world origin are dropped as absurd
/// ranges (OpenVDB coordinates are 32-bit ints; the update reach must not overflow them).
struct PointLimits {
    Vec3f origin_W = Vec3f::Zero();
    float min_range2 = 0.0f;  ///< closer (squared, m^2): kAtOrigin
    float max_range2 = 0.0f;  ///< further (squared, m^2), or beyond max_index: kRange
    float inv_voxel = 1.0f;
    float max_index = 1e9f;
};

/// A batch of points classified for phase 1 (integrator, bin): per point its status, and for
/// a valid point its cell (SoA), floor((p / voxel + 1/2) * divisions) per axis: the voxel
/// index (divisions 1) or the half-voxel cell (2). At most kCapacity points.
struct PointCells {
    static constexpr std::size_t kCapacity = 256;
    std::int32_t status[kCapacity];
    std::int32_t x[kCapacity], y[kCapacity], z[kCapacity];
};

/// The reference for one point: the checks in order (non-finite, at the origin, out of range
/// or index) and the cell, exactly as voxelOf's float arithmetic. classifyPoints must agree.
template <int kDivisions>
inline std::int32_t classifyPoint(const Vec3f& p, const PointLimits& lim, std::int32_t cell[3]) {
    static_assert(kDivisions == 1 || kDivisions == 2, "a cell is a voxel or half a voxel");
    if (!(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()))) return kNonFinite;
    const float range2 = (p - lim.origin_W).squaredNorm();  // x^2 + (y^2 + z^2)
    if (range2 < lim.min_range2) return kAtOrigin;
    const float u[3] = {p.x() * lim.inv_voxel, p.y() * lim.inv_voxel, p.z() * lim.inv_voxel};
    if (range2 > lim.max_range2 ||
        !(std::abs(u[0]) < lim.max_index && std::abs(u[1]) < lim.max_index && std::abs(u[2]) < lim.max_index))
        return kRange;
    for (int a = 0; a < 3; ++a)
        cell[a] = kDivisions == 1 ? floorToInt(u[a] + 0.5f) : floorToInt((u[a] + 0.5f) * 2.0f);
    return kValid;
}

/// classifyPoint for n <= PointCells::kCapacity points, four at a time with SSE2 (the same
/// float operations in the same order, so the same bits), the rest one by one. The checks and
/// the floors are branch-free, which is most of phase 1's time per point.
template <int kDivisions>
inline void classifyPoints(const Vec3f* points, std::size_t n, const PointLimits& lim, PointCells& out) {
    std::size_t i = 0;
#if defined(__SSE2__)
    static_assert(sizeof(Vec3f) == 3 * sizeof(float), "Vec3f is three packed floats");
    const __m128 ox = _mm_set1_ps(lim.origin_W.x()), oy = _mm_set1_ps(lim.origin_W.y()),
                 oz = _mm_set1_ps(lim.origin_W.z());
    const __m128 min2 = _mm_set1_ps(lim.min_range2), max2 = _mm_set1_ps(lim.max_range2);
    const __m128 inv = _mm_set1_ps(lim.inv_voxel), max_index = _mm_set1_ps(lim.max_index);
    const __m128 half = _mm_set1_ps(0.5f), two = _mm_set1_ps(2.0f), zero = _mm_setzero_ps();
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    // floor for |v| < 2^31, as floorToInt: truncate, minus one where that rounded up.
    auto floorInt = [](__m128 v) {
        const __m128i t = _mm_cvttps_epi32(v);
        return _mm_add_epi32(t, _mm_castps_si128(_mm_cmplt_ps(v, _mm_cvtepi32_ps(t))));
    };
    for (; i + 4 <= n; i += 4) {
        // Four packed xyz triples: m0 = x0 y0 z0 x1, m1 = y1 z1 x2 y2, m2 = z2 x3 y3 z3.
        const float* f = points[i].data();
        const __m128 m0 = _mm_loadu_ps(f), m1 = _mm_loadu_ps(f + 4), m2 = _mm_loadu_ps(f + 8);
        const __m128 x01 = _mm_shuffle_ps(m0, m0, _MM_SHUFFLE(3, 0, 3, 0));  // x0 x1 x0 x1
        const __m128 x23 = _mm_shuffle_ps(m1, m2, _MM_SHUFFLE(1, 1, 2, 2));  // x2 x2 x3 x3
        const __m128 px = _mm_shuffle_ps(x01, x23, _MM_SHUFFLE(2, 0, 1, 0));
        const __m128 y01 = _mm_shuffle_ps(m0, m1, _MM_SHUFFLE(0, 0, 1, 1));  // y0 y0 y1 y1
        const __m128 y23 = _mm_shuffle_ps(m1, m2, _MM_SHUFFLE(2, 2, 3, 3));  // y2 y2 y3 y3
        const __m128 py = _mm_shuffle_ps(y01, y23, _MM_SHUFFLE(2, 0, 2, 0));
        const __m128 z01 = _mm_shuffle_ps(m0, m1, _MM_SHUFFLE(1, 1, 2, 2));  // z0 z0 z1 z1
        const __m128 z23 = _mm_shuffle_ps(m2, m2, _MM_SHUFFLE(3, 0, 3, 0));  // z2 z3 z2 z3
        const __m128 pz = _mm_shuffle_ps(z01, z23, _MM_SHUFFLE(1, 0, 2, 0));
        // Finite: v - v is 0 (NaN for NaN and infinities).
        const __m128 finite = _mm_and_ps(_mm_and_ps(_mm_cmpeq_ps(_mm_sub_ps(px, px), zero),
                                                    _mm_cmpeq_ps(_mm_sub_ps(py, py), zero)),
                                         _mm_cmpeq_ps(_mm_sub_ps(pz, pz), zero));
        const __m128 dx = _mm_sub_ps(px, ox), dy = _mm_sub_ps(py, oy), dz = _mm_sub_ps(pz, oz);
        // Eigen's squaredNorm order: x^2 + (y^2 + z^2).
        const __m128 range2 =
            _mm_add_ps(_mm_mul_ps(dx, dx), _mm_add_ps(_mm_mul_ps(dy, dy), _mm_mul_ps(dz, dz)));
        const __m128 at_origin = _mm_cmplt_ps(range2, min2);
        const __m128 ux = _mm_mul_ps(px, inv), uy = _mm_mul_ps(py, inv), uz = _mm_mul_ps(pz, inv);
        const __m128 in_index =
            _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(_mm_and_ps(ux, abs_mask), max_index),
                                  _mm_cmplt_ps(_mm_and_ps(uy, abs_mask), max_index)),
                       _mm_cmplt_ps(_mm_and_ps(uz, abs_mask), max_index));
        const __m128 out_of_range = _mm_or_ps(_mm_cmpgt_ps(range2, max2), _mm_andnot_ps(in_index, finite));
        // status = !finite ? 1 : at_origin ? 2 : out_of_range ? 3 : 0, as masks of 1, 2 and 3.
        const __m128i not_finite = _mm_castps_si128(_mm_andnot_ps(finite, _mm_castsi128_ps(_mm_set1_epi32(-1))));
        // A non-finite point's range2 is NaN or infinite, never below min2.
        const __m128i origin_only = _mm_castps_si128(at_origin);
        const __m128i range_only = _mm_andnot_si128(_mm_or_si128(not_finite, origin_only),
                                                    _mm_castps_si128(out_of_range));
        const __m128i status = _mm_or_si128(
            _mm_or_si128(_mm_and_si128(not_finite, _mm_set1_epi32(kNonFinite)),
                         _mm_and_si128(origin_only, _mm_set1_epi32(kAtOrigin))),
            _mm_and_si128(range_only, _mm_set1_epi32(kRange)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out.status + i), status);
        auto cell = [&](__m128 u) {
            const __m128 v = _mm_add_ps(u, half);
            return floorInt(kDivisions == 1 ? v : _mm_mul_ps(v, two));
        };
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out.x + i), cell(ux));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out.y + i), cell(uy));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out.z + i), cell(uz));
    }
#endif
    for (; i < n; ++i) {
        std::int32_t c[3] = {0, 0, 0};
        out.status[i] = classifyPoint<kDivisions>(points[i], lim, c);
        out.x[i] = c[0];
        out.y[i] = c[1];
        out.z[i] = c[2];
    }
}

}  // namespace vdbmap::detail
