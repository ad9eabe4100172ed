// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace vdbmap::texture {

/// Radial vignetting model of the paper (Sec. 5.2.1, after Rohlfing 2012):
///   g(r) = 1 + a r^2 + b r^4 + c r^6,  I'(u, v) = g(r) * I(u, v),
///   r = |(u, v) - (cu, cv)| / sqrt(cu^2 + cv^2),
/// with (cu, cv) the image centre ((width - 1) / 2, (height - 1) / 2) in pixels, as the
/// paper's "image center" (not the principal point).
struct VignettingParams {
    double a = 0, b = 0, c = 0;
    bool isIdentity() const { return a == 0 && b == 0 && c == 0; }
};

/// Normalised radius r of pixel (u, v) (paper's vignetting equation).
double vignettingRadius(double u, double v, double cu, double cv);

/// Gain g(r) = 1 + a r^2 + b r^4 + c r^6.
double vignettingGain(const VignettingParams& params, double r);

/// Multiplies every pixel of a CV_32FC3 image by g(r) in place (Paper: I' = g(r) I). The image
/// may be a crop whose top-left pixel is `origin` of the camera's image. Throws InvalidInput
/// on another image type.
void correctVignetting(cv::Mat& image_f32, const VignettingParams& params, double cu, double cv,
                       cv::Point origin = {0, 0});

/// One face seen in one view, for the estimation: the mean luminance of the face and the
/// normalised radius of its centroid.
struct VignettingSample {
    std::uint32_t face = 0;
    std::uint32_t view = 0;
    float luminance = 0;  ///< > 0
    float radius = 0;     ///< paper's normalised r
};

/// Result of estimateVignetting for one camera.
struct VignettingEstimate {
    VignettingParams params;
    std::size_t pairs_used = 0;   ///< observation pairs in the final fit
    double rms_log_residual = 0;  ///< of the final fit, natural log units
};

/// Estimates (a, b, c) of every camera from overlapping observations (beyond the paper):
/// the same face seen in views i and j gives
///   log L_i - log L_j = (e_i - e_j) - (h_cam(i)(r_i) - h_cam(j)(r_j)),
/// with e a per-view log exposure (nuisance) and h(r) = alpha r^2 + beta r^4 + gamma r^6
/// = log g(r). The linear least-squares system over all pairs (each observation paired with the
/// face's first observation) is solved with two rounds of outlier rejection (|residual| >
/// 3 * 1.4826 * MAD: occluders), then (a, b, c) are fitted to exp(h(r)) on r in [0, 1].
/// `view_camera[v]` is the camera of view v (< num_cameras). Cameras with too few samples get
/// the identity model. Samples of the same face must be adjacent in `samples`.
std::vector<VignettingEstimate> estimateVignetting(const std::vector<VignettingSample>& samples,
                                                   const std::vector<std::uint32_t>& view_camera,
                                                   std::size_t num_cameras);

}  // namespace vdbmap::texture
