// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <random>

#include "vdbmap/core/Types.h"
#include "vdbmap/sim/SimScene.h"

namespace vdbmap {

/// Camera effects of the simulator.
struct ImagingOptions {
    std::array<double, 3> vignetting_abc{0.3, 0.1, 0.05};  ///< g(r) coefficients a, b, c
    int label_noise_px = 0;
};

/// The paper's vignetting gain g(r) = 1 + a r^2 + b r^4 + c r^6 (Rohlfing 2012) at pixel
/// (u, v), r normalised by the distance of the image centre (cx, cy) to the corner.
double vignettingGain(const std::array<double, 3>& abc, double u, double v, double cx,
                      double cy);

/// In place on a BGR8 image: I <- exposure * I / g(r), centre = image centre.
void applyVignettingAndExposure(cv::Mat& image_bgr, const ImagingOptions& options,
                                double exposure);

/// Jitters class boundaries of an 8-bit label image: pixels within label_noise_px of a
/// boundary take the label of a pixel shifted by a random offset (one offset per 8x8 block).
void addLabelNoise(cv::Mat& labels, const ImagingOptions& options, std::mt19937_64& rng);

/// A box "pedestrian" (class 11, 0.5 x 0.5 x 1.8 m) standing on the ground 6-10 m ahead of the
/// vehicle pose `T_W_V`, offset sideways at random.
SimScene makeOccluder(const Isometry3d& T_W_V, double ahead_m, std::mt19937_64& rng,
                      std::uint64_t seed);

}  // namespace vdbmap
