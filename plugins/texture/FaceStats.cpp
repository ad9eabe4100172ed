// SPDX-License-Identifier: Apache-2.0
#include "FaceStats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "Raster.h"
#include "vdbmap/Error.h"

namespace vdbmap::texture {

cv::Mat toFloatBgr(const cv::Mat& bgr_u8) {
    if (bgr_u8.empty() || bgr_u8.type() != CV_8UC3) {
        throw InvalidInput("texture: expected an 8-bit 3-channel image, got " +
                           (bgr_u8.empty() ? std::string("an empty image")
                                           : "type " + std::to_string(bgr_u8.type())));
    }
    cv::Mat out;
    bgr_u8.convertTo(out, CV_32FC3);
    return out;
}

cv::Mat gradientMagnitude(const cv::Mat& bgr_f32) {
    cv::Mat grey, gx, gy, magnitude;
    cv::cvtColor(bgr_f32, grey, cv::COLOR_BGR2GRAY);
    // Sobel 3x3 sums 8x the derivative of a linear ramp: scale back to intensity per pixel.
    cv::Sobel(grey, gx, CV_32F, 1, 0, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
    cv::Sobel(grey, gy, CV_32F, 0, 1, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
    cv::magnitude(gx, gy, magnitude);
    return magnitude;
}

std::vector<std::vector<std::uint64_t>> observationsPerView(const Visibility& vis,
                                                            std::size_t num_views) {
    std::vector<std::vector<std::uint64_t>> per_view(num_views);
    for (std::uint64_t i = 0; i < vis.obs.size(); ++i) {
        const std::uint32_t view = vis.obs[i].view;
        if (view >= num_views) {
            throw InvalidInput("texture: visibility refers to view " + std::to_string(view) +
                               " but there are " + std::to_string(num_views) + " views");
        }
        per_view[view].push_back(i);
    }
    return per_view;
}

cv::Rect observedBounds(const Visibility& vis, const std::vector<std::uint64_t>& obs_indices,
                        cv::Size image_size, int margin_px) {
    float x_min = std::numeric_limits<float>::infinity(), y_min = x_min;
    float x_max = -x_min, y_max = -x_min;
    for (const std::uint64_t index : obs_indices) {
        for (const Eigen::Vector2f& p : vis.obs[index].pixels) {
            x_min = std::min(x_min, p.x());
            y_min = std::min(y_min, p.y());
            x_max = std::max(x_max, p.x());
            y_max = std::max(y_max, p.y());
        }
    }
    if (!(x_min <= x_max && y_min <= y_max)) return {};
    // Clamp in float first: corners far outside the image must not overflow an int.
    auto clampTo = [](float value, int size) {
        return static_cast<int>(std::clamp(value, -1.0f, static_cast<float>(size)));
    };
    const int x0 = std::max(0, clampTo(std::floor(x_min), image_size.width) - margin_px);
    const int y0 = std::max(0, clampTo(std::floor(y_min), image_size.height) - margin_px);
    const int x1 =
        std::min(image_size.width, clampTo(std::ceil(x_max), image_size.width) + margin_px + 1);
    const int y1 =
        std::min(image_size.height, clampTo(std::ceil(y_max), image_size.height) + margin_px + 1);
    if (x0 >= x1 || y0 >= y1) return {};
    return {x0, y0, x1 - x0, y1 - y0};
}

void computeObservationStats(const cv::Mat& bgr_f32, cv::Point origin, cv::Size image_size,
                             const Visibility& vis, const std::vector<std::uint64_t>& obs_indices,
                             bool with_quality, std::vector<ObservationStats>& stats) {
    if (obs_indices.empty()) return;
    // Channels: B G R |grad|; integral image in double (exact sums of ~1e6 values).
    cv::Mat channels;
    if (with_quality) {
        cv::Mat grad = gradientMagnitude(bgr_f32);
        cv::merge(std::vector<cv::Mat>{bgr_f32, grad}, channels);
    } else {
        channels = bgr_f32;
    }
    const int num_channels = channels.channels();
    cv::Mat integral;
    cv::integral(channels, integral, CV_64F);
    // Pixel (x, y) of the whole image is (x - origin.x, y - origin.y) of the crop.
    const int width = image_size.width, height = image_size.height;
    const int stride = num_channels;
    auto at = [&](int y, int x) {
        return integral.ptr<double>(y - origin.y) + (x - origin.x) * stride;
    };

    for (const std::uint64_t index : obs_indices) {
        const FaceObservation& obs = vis.obs[index];
        double sums[4] = {0, 0, 0, 0};
        const long covered =
            rasterizeSpans(obs.pixels, width, height, [&](int y, int x_begin, int x_end) {
                const double* a = at(y, x_begin);
                const double* b = at(y, x_end);
                const double* c = at(y + 1, x_begin);
                const double* d = at(y + 1, x_end);
                for (int k = 0; k < num_channels; ++k) sums[k] += d[k] - c[k] - b[k] + a[k];
            });
        ObservationStats& out = stats[index];
        if (covered > 0) {
            out.pixels = static_cast<std::uint32_t>(covered);
            out.mean_bgr =
                Vec3f(float(sums[0] / covered), float(sums[1] / covered), float(sums[2] / covered));
            out.quality = with_quality ? static_cast<float>(sums[3]) : 0.0f;
        } else {
            // Smaller than a pixel: the pixel nearest to the centroid, weighted by the area.
            const Eigen::Vector2f centroid = (obs.pixels[0] + obs.pixels[1] + obs.pixels[2]) / 3.0f;
            const int x = std::clamp(static_cast<int>(std::lround(centroid.x())), 0, width - 1);
            const int y = std::clamp(static_cast<int>(std::lround(centroid.y())), 0, height - 1);
            const cv::Vec3f c = bgr_f32.at<cv::Vec3f>(y - origin.y, x - origin.x);
            out.pixels = 1;
            out.mean_bgr = Vec3f(c[0], c[1], c[2]);
            if (with_quality) {
                const double* a = at(y, x);
                const double* b = at(y, x + 1);
                const double* cc = at(y + 1, x);
                const double* d = at(y + 1, x + 1);
                out.quality = static_cast<float>((d[3] - cc[3] - b[3] + a[3]) * obs.area_px);
            } else {
                out.quality = 0.0f;
            }
        }
    }
}

}  // namespace vdbmap::texture
