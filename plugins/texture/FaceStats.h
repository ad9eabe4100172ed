// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "TextureTypes.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::texture {

/// Gradient magnitude of the grey image of a CV_32FC3 BGR image (Sobel 3x3 scaled to a
/// per-pixel derivative), CV_32F.
cv::Mat gradientMagnitude(const cv::Mat& bgr_f32);

/// Data term and mean colours of the faces seen in one view (paper Eq. E_Q):
///   E_Q(F, I) = integral over the projection phi(F, I) of |grad I(p)|,
/// evaluated as the sum over the pixel centres inside the projected triangle, with row spans
/// over an integral image (O(rows) per face instead of O(area)). A face smaller than a pixel
/// uses the pixel nearest to its projected centroid. `obs_indices` index `vis.obs`; the results
/// go to `stats[obs_index]`. With `with_quality` false only the colours are computed.
/// `bgr_f32` may be a crop of the view's image: its top-left pixel is `origin` of an image of
/// `image_size` (the pixel coordinates of `vis` are the whole image's). The crop must contain
/// observedBounds(vis, obs_indices, image_size, kStatsMarginPx).
void computeObservationStats(const cv::Mat& bgr_f32, cv::Point origin, cv::Size image_size,
                             const Visibility& vis, const std::vector<std::uint64_t>& obs_indices,
                             bool with_quality, std::vector<ObservationStats>& stats);

/// The pixels of the whole image a view's statistics read: beyond the observations' projected
/// corners, one pixel for rounding and one for the 3x3 gradient.
inline constexpr int kStatsMarginPx = 2;

/// The bounding box of the projected corners of `obs_indices`, grown by `margin_px` and clipped
/// to the image (empty if nothing lies inside). Why: a tile sees a small part of most of its
/// views' images; the statistics then cost the part, not the whole image.
cv::Rect observedBounds(const Visibility& vis, const std::vector<std::uint64_t>& obs_indices,
                        cv::Size image_size, int margin_px);

/// For every view, the indices into `vis.obs` of its observations (inverse of the CSR).
std::vector<std::vector<std::uint64_t>> observationsPerView(const Visibility& vis,
                                                            std::size_t num_views);

/// Converts an 8-bit BGR image to CV_32FC3 (0..255). Throws InvalidInput on an empty image or
/// another type.
cv::Mat toFloatBgr(const cv::Mat& bgr_u8);

}  // namespace vdbmap::texture
