// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <opencv2/core.hpp>

#include <vector>

#include "vdbmap/eval/GtViews.h"
#include "vdbmap/io/MeshIO.h"

namespace vdbmap {

class Raycaster;

/// Photometric scores of a textured mesh rendered from held-out views.
struct TextureMetrics {
    std::size_t views = 0;
    std::size_t pixels_compared = 0;  ///< pixels where both the render and the gt have surface
    double coverage = 0;  ///< pixels_compared / ground-truth surface pixels
    double mae = 0;       ///< mean absolute error per channel, 0..255
    /// 10 log10(255^2 / MSE) over the compared pixels and channels; capped at kMaxPsnrDb for
    /// identical images (MSE = 0).
    double psnr_db = 0;
    /// The PSNR of each view alone (same rule), in the order of the views.
    std::vector<double> view_psnr_db;
    static constexpr double kMaxPsnrDb = 100.0;
};

/// Accumulates the per-channel absolute and squared errors of two 8-bit BGR images over the
/// pixels where `gt_surface` (CV_8UC1, empty = everywhere) and `rendered_mask` (empty =
/// everywhere) are non-zero; counts the gt surface pixels for the coverage. Throws
/// InvalidInput if the images differ in size or type.
void accumulateImageError(const cv::Mat& rendered_bgr, const cv::Mat& rendered_mask,
                          const cv::Mat& gt_bgr, const cv::Mat& gt_surface,
                          TextureMetrics& metrics, double& sum_abs, double& sum_sq,
                          std::size_t& gt_pixels);
/// Turns the sums of accumulateImageError into MAE, PSNR and coverage.
void finishTextureMetrics(TextureMetrics& metrics, double sum_abs, double sum_sq,
                          std::size_t gt_pixels);

/// Renders the textured prediction (no shading: the texture already holds the shading) from
/// every view and compares it with the view's image where both the render and the ground truth
/// have surface. The ground-truth surface comes from `gt` (a Raycaster on the ground-truth
/// mesh) if non-null, else from non-black gt pixels. `gt_images[i]` belongs to `views[i]`.
/// `renders` (optional) receives each view's render (8-bit BGR, black where the prediction has no
/// surface), to look at. Throws InvalidInput if sizes disagree.
TextureMetrics evaluateTexture(const ObjMesh& pred, const std::vector<cv::Mat>& pred_textures,
                               const std::vector<GtView>& views,
                               const std::vector<cv::Mat>& gt_images, const Raycaster* gt,
                               std::vector<cv::Mat>* renders = nullptr);

}  // namespace vdbmap
