// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// The elevation rings of a spinning LiDAR (one laser per ring), estimated from one scan in
/// its own frame L (z up): for any elevation, the angle to the next ring towards the horizon.
///
/// A grazing surface (the road) is sampled ring by ring: beyond a point at range r, hit at the
/// grazing angle alpha (sin alpha = |n . d|, n the surface normal, d the unit ray), the next
/// ring, dtheta further towards the horizon, meets a plane only after
///   g = r sin(e dtheta) / sin(alpha - e dtheta)                      (RingSpacing::surfaceGap)
/// (the triangle sensor - point - next point; e the share of the ring step that turns the ray
/// along the surface: 1 on the ground, 0 on a wall the ray grazes sideways). Nothing samples the
/// surface in between. The adaptive band behind a point can reach that far (Truncation.h,
/// `grazing_band_to_next_ring`), so the gap is closed from its near ring instead of staying a
/// hole.
class RingSpacing {
public:
    /// Estimates the rings from every `stride`-th point of `points_L`: the sines of their
    /// elevations are binned at ~0.014 deg; a ring is a run of occupied bins (a one-bin hole
    /// inside allowed), its elevation the run's mean. valid() is false with fewer than 3 rings,
    /// or when runs wider than 0.3 deg hold more than a fifth of the points (not a spinning
    /// multi-beam sensor, or one whose lasers sit off its origin, as a real HDL-64's: their
    /// elevations seen from the origin change with range), or when more than half the bins
    /// between the lowest and the highest point hold one (no empty space between rings).
    static RingSpacing estimate(PointSpan points_L, std::size_t stride = 4);
    /// From known ring elevations (radians, any order), e.g. a sensor's calibration.
    static RingSpacing fromElevations(std::vector<double> elevations_rad);

    bool valid() const { return !gap_rad_.empty(); }
    std::size_t rings() const { return rings_; }

    /// The angle (rad) from the ring nearest to sin(elevation) `sin_elev` to the next ring
    /// towards the horizon (up for rings below it, down for rings above it); 0 for the
    /// outermost ring on that side, or when not valid().
    float gapTowardsHorizon(float sin_elev) const {
        if (gap_rad_.empty()) return 0.0f;
        const float x = (sin_elev + 1.0f) * (0.5f * static_cast<float>(kBins));
        const int i = static_cast<int>(x);
        return gap_rad_[static_cast<std::size_t>(i < 0 ? 0 : (i >= kBins ? kBins - 1 : i))];
    }

    /// g above: the stretch of a plane with normal `n_W` (unit) beyond the point at `range_m`
    /// on the unit ray `dir_W` that the next ring does not sample; `up_W` is the sensor's z axis
    /// in the world frame. 0 when not valid() or nothing is left unsampled; +infinity when the
    /// next ring misses the plane (alpha <= e dtheta).
    template <typename Vec3>
    auto surfaceGap(const Vec3& dir_W, const Vec3& n_W, const Vec3& up_W, double range_m) const {
        using Scalar = typename Vec3::Scalar;
        const Scalar s = dir_W.dot(up_W);  // sin(elevation)
        const Scalar dtheta = static_cast<Scalar>(gapTowardsHorizon(static_cast<float>(s)));
        if (!(dtheta > Scalar(0))) return Scalar(0);
        // The ray turns along n_perp (n's part across the ray) to move along the surface; the
        // ring step turns it along the elevation direction up - s d. e = the cosine between them.
        const Scalar c = n_W.dot(dir_W);
        const Vec3 n_perp = n_W - c * dir_W;
        const Vec3 elev = up_W - s * dir_W;
        // A surface (nearly) facing the ray: the ring step does not move along it (n_perp ~ 0).
        if (!(n_perp.squaredNorm() > Scalar(1e-6))) return Scalar(0);
        const Scalar den2 = n_perp.squaredNorm() * elev.squaredNorm();
        if (!(den2 > Scalar(0))) return Scalar(0);
        const Scalar step = std::abs(n_perp.dot(elev)) / std::sqrt(den2) * dtheta;  // e dtheta
        // sin(alpha - step) = sin(alpha) cos(step) - cos(alpha) sin(step), with the series of
        // sin and cos (step <= ~0.3 rad: relative error < 1e-5).
        const Scalar step2 = step * step;
        const Scalar sin_step = step * (Scalar(1) - step2 / Scalar(6));
        const Scalar cos_step = Scalar(1) - step2 / Scalar(2) + step2 * step2 / Scalar(24);
        const Scalar sin_alpha = std::abs(c);
        const Scalar cos_alpha = std::sqrt(std::max(Scalar(0), Scalar(1) - c * c));
        const Scalar den = sin_alpha * cos_step - cos_alpha * sin_step;
        if (!(den > Scalar(0))) return std::numeric_limits<Scalar>::infinity();
        return static_cast<Scalar>(range_m) * sin_step / den;
    }

    static constexpr int kBins = 8192;  ///< bins of sin(elevation) over [-1, 1]

private:
    std::vector<float> gap_rad_;  ///< per bin; empty when not valid
    std::size_t rings_ = 0;
};

}  // namespace vdbmap
