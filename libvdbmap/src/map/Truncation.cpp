// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/Truncation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vdbmap/Error.h"

namespace vdbmap {

TruncationMode parseTruncationMode(const std::string& text) {
    if (text == "adaptive") return TruncationMode::Adaptive;
    if (text == "paper") return TruncationMode::Paper;
    if (text == "fixed") return TruncationMode::Fixed;
    throw ConfigError("truncation_mode must be 'adaptive', 'paper' or 'fixed', got '" + text + "'");
}

const char* truncationModeName(TruncationMode mode) {
    switch (mode) {
        case TruncationMode::Adaptive: return "adaptive";
        case TruncationMode::Paper: return "paper";
        case TruncationMode::Fixed: return "fixed";
    }
    return "adaptive";
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
    if (!std::isfinite(p.max_along_ray_m) || p.max_along_ray_m < 0.0 ||
        (p.max_along_ray_m > 0.0 && p.max_along_ray_m < p.max_m))
        bad("truncation_max_along_ray_m", p.max_along_ray_m, "0 (= truncation_max_m) or >= truncation_max_m");
    if (!std::isfinite(p.grazing_band_m) || p.grazing_band_m < 0.0)
        bad("grazing_band_voxels", p.grazing_band_m, ">= 0");
}

TruncationParams resolveTruncation(const TruncationParams& params, double voxel_size_m) {
    TruncationParams r = params;
    if (r.max_m == 0.0) r.max_m = r.max_voxels * voxel_size_m;
    if (r.min_m == 0.0) r.min_m = std::min(r.min_voxels * voxel_size_m, r.max_m);
    if (r.grazing_band_m == 0.0) r.grazing_band_m = r.grazing_band_voxels * voxel_size_m;
    if (r.reference_points == 0.0)
        r.reference_points = referencePointsForDensity(r.reference_density_pts_m2, voxel_size_m);
    return r;
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

double maxAlongRay(const TruncationParams& p) {
    return p.max_along_ray_m > 0.0 ? p.max_along_ray_m : p.max_m;
}

RayBand rayBandFor(const TruncationParams& p, double eps_m, double cos_incidence, double gap_m) {
    if (p.mode != TruncationMode::Adaptive) return {eps_m, eps_m};
    // A voxel at t along the ray lies t |n . d| from the block's plane: the ray band [-eps, eps]
    // spans only eps |n . d| across a grazing surface. The adaptive band spans at least b across
    // it in front (b / |n . d| along the ray, up to L_max); behind, max(eps, b) along the ray
    // but no deeper than b across the surface.
    const double l_max = std::max(maxAlongRay(p), eps_m);
    const double c = std::clamp(cos_incidence, 0.0, 1.0);
    const AdaptiveBand<double> band =
        adaptiveBand(eps_m, c, p.grazing_band_m, l_max, p.grazing_band_both_sides, gap_m);
    return {band.front_m, band.back_m};
}

double maxHalfLength(const TruncationParams& p) {
    return p.mode == TruncationMode::Adaptive ? std::max(maxAlongRay(p), p.max_m) : p.max_m;
}

}  // namespace vdbmap
