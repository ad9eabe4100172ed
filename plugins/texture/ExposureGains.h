// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "TextureTypes.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::texture {

/// Options of the joint exposure estimation (one gain per image).
struct ExposureOptions {
    float min_luminance = 8.0f;    ///< darker observations carry no gain signal (0..255)
    float max_luminance = 250.0f;  ///< brighter ones may be clipped
    std::uint32_t min_pixels = 4;  ///< observations with fewer pixel centres are too noisy
    /// Faces used at most (a deterministic stride over the usable faces): the gains are a few
    /// hundred unknowns, a few hundred thousand faces determine them.
    std::size_t max_faces = 200000;
    int irls_iterations = 4;     ///< Huber reweighting rounds (moving objects, specularities)
    double huber_log = 0.05;     ///< Huber threshold on the log residual (~5 %)
    int max_cg_iterations = 2000;
    double tolerance = 1e-10;  ///< relative residual of the conjugate gradient
};

/// Gains and what they were estimated from.
struct ExposureResult {
    std::vector<double> gain;  ///< per view; observed = gain * exposure-free colour
    std::size_t faces_used = 0;
    std::size_t observations_used = 0;
    std::vector<std::uint32_t> views_without_overlap;  ///< kept at gain 1
    int cg_iterations = 0;  ///< total over the reweighting rounds
};

/// Estimates one exposure gain per view jointly from the faces several views see. With
/// l_fv = log luminance of face f in view v, a_v = log gain, b_f = log radiance:
///   minimise  sum_{f,v} w_fv (l_fv - a_v - b_f)^2   subject to  mean_v a_v = 0
/// (the gauge: only ratios of gains are observable). b_f is eliminated in closed form
/// (b_f = weighted mean of l_fv - a_v) and the reduced normal equations in a are solved by a
/// Jacobi-preconditioned conjugate gradient, matrix-free (its cost is linear in the
/// observations); w_fv are Huber IRLS weights. Views in no overlap keep gain 1; a tiny prior
/// a_v -> 0 fixes each unconnected group of views. Observations with keep[obs] == 0 (if keep
/// is given), dark, saturated or tiny ones are ignored. Throws InvalidInput on size mismatch.
ExposureResult estimateExposureGains(const Visibility& vis,
                                     const std::vector<ObservationStats>& stats,
                                     std::size_t num_views, const ExposureOptions& options,
                                     const std::vector<char>* keep = nullptr);

/// Divides the mean colour and E_Q (both linear in the image) of every observation by the
/// gain of its view: the statistics of the exposure-corrected images.
void applyExposureGains(const Visibility& vis, const std::vector<double>& gain,
                        std::vector<ObservationStats>& stats);

/// Rec. 601 luminance of a BGR colour.
inline float luminanceBgr(const Vec3f& bgr) {
    return 0.114f * bgr[0] + 0.587f * bgr[1] + 0.299f * bgr[2];
}

}  // namespace vdbmap::texture
