// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include "vdbmap/map/BlockStats.h"

namespace vdbmap {

/// How the truncation distance eps is chosen.
enum class TruncationMode {
    Adaptive,  ///< per block, paper Eq. (4)
    Fixed,     ///< eps = truncation_max_m everywhere (same code path, for comparisons)
};

/// Parses "adaptive" / "fixed". Throws ConfigError naming the bad value.
TruncationMode parseTruncationMode(const std::string& text);
/// "adaptive" / "fixed".
const char* truncationModeName(TruncationMode mode);

/// Parameters of the truncation distance.
struct TruncationParams {
    TruncationMode mode = TruncationMode::Adaptive;
    double min_m = 0.10;  ///< eps_min
    double max_m = 0.30;  ///< eps_max
    /// k: importance of the flatness (unitless, because n enters relative to n_ref).
    double flatness_k = 1.0;
    /// n_ref: the point count per block at which a perfectly flat block gets k * eps_max.
    /// The paper's n enters as n / n_ref, so k is unitless. The stage derives n_ref from a
    /// surface density (referencePointsForDensity) so that eps adapts alike at every voxel size.
    double reference_points = 100.0;
};

/// n_ref of an 8^3 block of edge 8 * voxel_size_m from a reference density of measurement
/// points per square metre of surface: density * (8 voxel)^2, the points a flat patch across
/// the block holds at that density. 156.25 / m^2 gives 100 at 0.10 m voxels, 6.25 at 0.025 m.
double referencePointsForDensity(double density_pts_m2, double voxel_size_m);

/// Throws ConfigError if the parameters are not finite, min <= 0, max < min, k < 0 or
/// reference_points <= 0. `who` prefixes the message (stage name).
void validateTruncation(const TruncationParams& params, const std::string& who);

/// Paper Eq. (4) with n relative to n_ref:
///   eps = clamp(max(eps_min, k * P_flat / (n / n_ref) * eps_max), eps_min, eps_max).
/// Degenerate blocks (plane.valid false: too few, collinear or identical points) get eps_max:
/// a sparse block needs the large truncation for completeness. Fixed mode: eps_max.
double truncationFor(const TruncationParams& params, const PlaneEstimate& plane, double n);

}  // namespace vdbmap
