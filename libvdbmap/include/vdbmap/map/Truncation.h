// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <string>

#include "vdbmap/map/BlockStats.h"

namespace vdbmap {

/// How the truncation distance eps is chosen and where the band of a measurement lies.
enum class TruncationMode {
    /// The default. eps per block from paper Eq. (4) (as Paper), and a band that keeps a width
    /// across the surface (rayBandFor; n the block normal, d the ray, b = grazing_band_m): a
    /// grazing surface (the road seen from a car) keeps a band of b across it and its updates
    /// reach along the surface towards the next ring, where the ray band of Paper/Fixed spans
    /// only eps |n . d| across it.
    Adaptive,
    Paper,  ///< per block, paper Eq. (4), band [-eps, eps] along the ray
    Fixed,  ///< eps = truncation_max_m everywhere, band along the ray (same code path)
};

/// Parses "adaptive" / "paper" / "fixed". Throws ConfigError naming the bad value.
TruncationMode parseTruncationMode(const std::string& text);
/// "adaptive" / "paper" / "fixed".
const char* truncationModeName(TruncationMode mode);

/// Parameters of the truncation distance. The defaults are the product's: what the
/// integrate.atsdf stage uses when its options are not given (the stage binds its options to
/// these fields). Lengths given in voxels apply where the metre field is 0;
/// resolveTruncation turns them into metres against the map's voxel size, and the functions
/// below take resolved parameters (AtsdfIntegrator resolves its config itself).
struct TruncationParams {
    TruncationMode mode = TruncationMode::Adaptive;
    /// eps_min in voxels, used when min_m is 0: the truncation of densely sampled or non-flat
    /// blocks. 4 = the paper's streets (0.40 m at 0.10 m voxels) and SUV (0.10 m at 0.025 m).
    double min_voxels = 4.0;
    /// eps_max in voxels, used when max_m is 0: the truncation of sparse, flat blocks and the
    /// farthest reach of a grazing ray. 8 = the paper's streets (0.80 m at 0.10 m voxels).
    double max_voxels = 8.0;
    /// eps_min (m); 0 = min_voxels voxels, but at most eps_max (a fixed-mode config gives only
    /// the max).
    double min_m = 0.0;
    double max_m = 0.0;  ///< eps_max (m); 0 = max_voxels voxels
    /// k: importance of the flatness (unitless, because n enters relative to n_ref).
    double flatness_k = 1.0;
    /// The surface density (points per m^2) that gives n_ref when reference_points is 0
    /// (referencePointsForDensity), so that eps adapts alike at every voxel size. 156.25 gives
    /// n_ref = 100 at 0.10 m voxels.
    double reference_density_pts_m2 = 156.25;
    /// n_ref: the point count per block at which a perfectly flat block gets k * eps_max.
    /// The paper's n enters as n / n_ref, so k is unitless. 0 = from reference_density_pts_m2.
    double reference_points = 0.0;
    /// Adaptive mode: L_max, the cap of the update's half-length along a grazing ray (m);
    /// 0 = max_m: the adaptive band then never reaches further along a ray than fixed eps_max's.
    /// Bounds the work per point and how far a plane is extrapolated.
    double max_along_ray_m = 0.0;
    /// Adaptive mode: b in voxels, used when grazing_band_m is 0.
    double grazing_band_voxels = 2.0;
    /// Adaptive mode: b, the least half-width of the band across a surface (along its normal),
    /// in metres; 0 = grazing_band_voxels voxels (both 0: no band beyond eps).
    double grazing_band_m = 0.0;
    /// Adaptive mode: the band reaches b across the surface behind the point as well
    /// (back = min(b / |n . d|, L_max) along the ray) instead of max(eps, b) along the ray: the
    /// gap between two rings of a grazing surface is then closed from both of them.
    bool grazing_band_both_sides = false;
    /// Adaptive mode: behind a grazing point the band reaches the next ring of the scan as well
    /// (back >= min(g, b / |n . d|, L_max), g the surface gap of RingSpacing::surfaceGap), where
    /// that ring lands on the same surface (the block there has a plane of about the same
    /// normal, within b): the integrator estimates the rings from each scan in its sensor frame.
    bool grazing_band_to_next_ring = true;
};

/// `params` with every length in metres: min_m, max_m and grazing_band_m from their voxel
/// counts where 0 (min_m at most max_m), reference_points from the density where 0. Resolved
/// parameters resolve to themselves.
TruncationParams resolveTruncation(const TruncationParams& params, double voxel_size_m);

/// n_ref of an 8^3 block of edge 8 * voxel_size_m from a reference density of measurement
/// points per square metre of surface: density * (8 voxel)^2, the points a flat patch across
/// the block holds at that density. 156.25 / m^2 gives 100 at 0.10 m voxels, 6.25 at 0.025 m.
double referencePointsForDensity(double density_pts_m2, double voxel_size_m);

/// Checks resolved parameters (resolveTruncation). Throws ConfigError if they are not finite, min <= 0, max < min, k < 0,
/// reference_points <= 0 or max_along_ray_m < 0 (or, when set, < max_m). `who` prefixes the
/// message (stage name).
void validateTruncation(const TruncationParams& params, const std::string& who);

/// Paper Eq. (4) with n relative to n_ref:
///   eps = clamp(max(eps_min, k * P_flat / (n / n_ref) * eps_max), eps_min, eps_max).
/// Degenerate blocks (plane.valid false: too few, collinear or identical points) get eps_max:
/// a sparse block needs the large truncation for completeness. Fixed mode: eps_max.
/// Adaptive and Paper modes share this eps; they differ in the direction it is measured in.
double truncationFor(const TruncationParams& params, const PlaneEstimate& plane, double n);

/// L_max of the adaptive mode: max_along_ray_m, or eps_max when 0 (the measured trade-off of a
/// longer reach is in docs/results/geometry.md: on the simulated street it closes more of the
/// grazing road, on a real scan it extrapolates the road's planes less accurately).
double maxAlongRay(const TruncationParams& params);

/// The extent of a point's update segment along its ray: t in [-front_m, back_m] around the
/// point (front: towards the sensor).
struct RayBand {
    double front_m = 0.0, back_m = 0.0;
};

/// The segment of a point whose block has `eps_m`, with cos_incidence = |n . d| (n: the normal
/// used for the point, d: the unit ray direction; 1 when the point has no normal):
///   Adaptive:      front = min(max(eps, b / c), L_max), back = min(max(eps, b), b / c)
///                  (b = grazing_band_m: the band spans at least b across the surface; it is
///                  widened only in front, in the free space the ray crossed); with
///                  grazing_band_both_sides, back = min(b / c, L_max); with a surface gap
///                  gap_m > 0 to the next ring behind the point (grazing_band_to_next_ring),
///                  back = max(back, min(gap, b / c, L_max))
///   Paper, Fixed:  front = back = eps                (the band along the ray)
RayBand rayBandFor(const TruncationParams& params, double eps_m, double cos_incidence,
                   double gap_m = 0.0);

/// min(b / c, L_max): how far along the ray a band b across the surface reaches (division-free
/// when the cap applies, so c = 0 is safe).
template <typename Scalar>
inline Scalar grazingReach(Scalar c, Scalar b, Scalar l_max) {
    return c * l_max > b ? b / c : l_max;
}

/// The adaptive branch of rayBandFor for eps <= l_max and c = |n . d| in [0, 1], in any
/// precision (the integrator's float, rayBandFor's double): {front, back} along the ray, and
/// the reach min(b / c, L_max) that the band behind may extend to when the next ring lands on
/// the same surface.
template <typename Scalar>
struct AdaptiveBand {
    Scalar front_m, back_m;
    Scalar reach_m;  ///< grazingReach(c, b, L_max)
    /// The band behind, extended to the next ring at surface gap `gap_m` behind the point
    /// (grazing_band_to_next_ring): max(back, min(gap, b / c, L_max)). A gap of 0 keeps it.
    Scalar backToRing(Scalar gap_m) const { return std::max(back_m, std::min(gap_m, reach_m)); }
};
/// gap: the surface gap to the next ring behind the point (0: none known).
template <typename Scalar>
inline AdaptiveBand<Scalar> adaptiveBand(Scalar eps, Scalar c, Scalar b, Scalar l_max,
                                         bool both_sides, Scalar gap = Scalar(0)) {
    const Scalar reach = grazingReach(c, b, l_max);
    const Scalar back = both_sides ? reach : std::min(std::max(eps, b), reach);
    AdaptiveBand<Scalar> band{std::min(std::max(eps, reach), l_max), back, reach};
    band.back_m = band.backToRing(gap);
    return band;
}

/// The longest half-length any point can get (the update reach of the integrator).
double maxHalfLength(const TruncationParams& params);

}  // namespace vdbmap
