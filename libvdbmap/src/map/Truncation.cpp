// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/Truncation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vdbmap/Error.h"

namespace vdbmap {

TruncationMode parseTruncationMode(const std::string& text) {
    if (text == "adaptive") return TruncationMode::Adaptive;
    if (text == "fixed") return TruncationMode::Fixed;
    throw ConfigError("truncation_mode must be 'adaptive' or 'fixed', got '" + text + "'");
}

const char* truncationModeName(TruncationMode mode) {
    return mode == TruncationMode::Adaptive ? "adaptive" : "fixed";
}

void validateTruncation(const TruncationParams& p, const std::string& who) {
    auto bad = [&](const char* key, double value, const char* rule) {
        std::ostringstream os;
        os << who << ": option '" << key << "' must be " << rule << ", got " << value;
        throw ConfigError(os.str());
    };
    if (!std::isfinite(p.min_m) || p.min_m <= 0.0) bad("truncation_min_m", p.min_m, "> 0");
    if (!std::isfinite(p.max_m) || p.max_m < p.min_m)
        bad("truncation_max_m", p.max_m, ">= truncation_min_m");
    if (!std::isfinite(p.flatness_k) || p.flatness_k < 0.0) bad("flatness_k", p.flatness_k, ">= 0");
    if (!std::isfinite(p.reference_points) || p.reference_points <= 0.0)
        bad("reference_points", p.reference_points, "> 0");
}

double referencePointsForDensity(double density_pts_m2, double voxel_size_m) {
    const double block_m = 8.0 * voxel_size_m;
    return density_pts_m2 * block_m * block_m;
}

double truncationFor(const TruncationParams& p, const PlaneEstimate& plane, double n) {
    if (p.mode == TruncationMode::Fixed) return p.max_m;
    // Degenerate block (too few / collinear / identical points): the sparse case, where the
    // large truncation keeps the surface complete.
    if (!plane.valid || !(n > 0.0)) return p.max_m;
    // Paper Eq. (4) with n relative to n_ref: eps = max(eps_min, k P_flat / (n / n_ref) eps_max),
    // clamped to [eps_min, eps_max].
    const double eps = std::max(p.min_m, p.flatness_k * plane.flatness * p.reference_points / n * p.max_m);
    return std::clamp(eps, p.min_m, p.max_m);
}

}  // namespace vdbmap
