// SPDX-License-Identifier: Apache-2.0
#include "sim/SimImaging.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "vdbmap/sim/Scenes.h"

namespace vdbmap {

double vignettingGain(const std::array<double, 3>& abc, double u, double v, double cx,
                      double cy) {
    // Paper: r = sqrt((u-u0)^2 + (v-v0)^2) / sqrt(u0^2 + v0^2), g = 1 + a r^2 + b r^4 + c r^6.
    const double r2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / (cx * cx + cy * cy);
    return 1.0 + abc[0] * r2 + abc[1] * r2 * r2 + abc[2] * r2 * r2 * r2;
}

void applyVignettingAndExposure(cv::Mat& image_bgr, const ImagingOptions& options,
                                double exposure) {
    // Image centre in the docs/DATA.md pixel convention (pixel centres at integers).
    const double cx = (image_bgr.cols - 1) / 2.0;
    const double cy = (image_bgr.rows - 1) / 2.0;
    for (int y = 0; y < image_bgr.rows; ++y) {
        for (int x = 0; x < image_bgr.cols; ++x) {
            const double s = exposure / vignettingGain(options.vignetting_abc, x, y, cx, cy);
            auto& p = image_bgr.at<cv::Vec3b>(y, x);
            for (int c = 0; c < 3; ++c) p[c] = cv::saturate_cast<std::uint8_t>(p[c] * s);
        }
    }
}

void addLabelNoise(cv::Mat& labels, const ImagingOptions& options, std::mt19937_64& rng) {
    const int px = options.label_noise_px;
    if (px <= 0) return;
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {2 * px + 1, 2 * px + 1});
    cv::Mat lo, hi;
    cv::erode(labels, lo, kernel);
    cv::dilate(labels, hi, kernel);
    const cv::Mat src = labels.clone();
    std::uniform_int_distribution<int> offset(-px, px);
    const int block = 8;
    for (int by = 0; by < labels.rows; by += block) {
        for (int bx = 0; bx < labels.cols; bx += block) {
            const int dx = offset(rng), dy = offset(rng);
            for (int y = by; y < std::min(by + block, labels.rows); ++y) {
                for (int x = bx; x < std::min(bx + block, labels.cols); ++x) {
                    if (lo.at<std::uint8_t>(y, x) == hi.at<std::uint8_t>(y, x)) continue;
                    const int sx = std::clamp(x + dx, 0, labels.cols - 1);
                    const int sy = std::clamp(y + dy, 0, labels.rows - 1);
                    labels.at<std::uint8_t>(y, x) = src.at<std::uint8_t>(sy, sx);
                }
            }
        }
    }
}

SimScene makeOccluder(const Isometry3d& T_W_V, double ahead_m, std::mt19937_64& rng,
                      std::uint64_t seed) {
    std::uniform_real_distribution<double> ahead(ahead_m - 2.0, ahead_m + 2.0);
    std::uniform_real_distribution<double> side(-1.5, 1.5);
    SimScene occluder;
    const std::uint32_t m = occluder.addMaterial("pedestrian", proceduralTexture("skin", seed));
    Isometry3d T_V_O = Isometry3d::Identity();
    T_V_O.translation() = Vec3d(ahead(rng), side(rng), 0.9);
    occluder.addBox(T_W_V * T_V_O, Vec3f(0.25f, 0.25f, 0.9f), 1.0f, m, 11);
    return occluder;
}

}  // namespace vdbmap
