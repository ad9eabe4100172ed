// SPDX-License-Identifier: Apache-2.0
#include "PhotoConsistency.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace vdbmap::texture {

Vec3f bgrToHsvCone(const Vec3f& bgr) {
    const float b = bgr.x() / 255.0f, g = bgr.y() / 255.0f, r = bgr.z() / 255.0f;
    const float v = std::max({r, g, b});
    const float min_c = std::min({r, g, b});
    const float chroma = v - min_c;
    const float s = v > 0 ? chroma / v : 0.0f;
    float h_deg = 0;
    if (chroma > 0) {
        if (v == r) {
            h_deg = 60.0f * std::fmod((g - b) / chroma + 6.0f, 6.0f);
        } else if (v == g) {
            h_deg = 60.0f * ((b - r) / chroma + 2.0f);
        } else {
            h_deg = 60.0f * ((r - g) / chroma + 4.0f);
        }
    }
    const float h_rad = h_deg * static_cast<float>(M_PI) / 180.0f;
    return {s * std::cos(h_rad), s * std::sin(h_rad), v};
}

namespace {

float median(std::vector<float> values) {
    const std::size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + mid, values.end());
    return values[mid];
}

}  // namespace

std::vector<char> photoConsistentViews(const std::vector<Vec3f>& colors_bgr,
                                       const PhotoConsistencyOptions& options) {
    const std::size_t n = colors_bgr.size();
    std::vector<char> keep(n, 1);
    if (n < static_cast<std::size_t>(std::max(options.min_views, 3))) return keep;
    std::vector<Vec3f> x(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = bgrToHsvCone(colors_bgr[i]);

    // Robust start: per-axis median and MAD.
    Vec3f mu, sigma;
    for (int d = 0; d < 3; ++d) {
        std::vector<float> axis(n);
        for (std::size_t i = 0; i < n; ++i) axis[i] = x[i][d];
        mu[d] = median(axis);
        for (std::size_t i = 0; i < n; ++i) axis[i] = std::abs(axis[i] - mu[d]);
        sigma[d] = std::max(1.4826f * median(axis), static_cast<float>(options.min_sigma));
    }
    // Mean shift with a Gaussian kernel (Waechter et al. 2014): the mean moves to the densest
    // mode, so a minority of differently coloured views (occluders) does not pull it.
    for (int it = 0; it < options.iterations; ++it) {
        Vec3f sum = Vec3f::Zero();
        float weight_sum = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const float d2 = ((x[i] - mu).array() / sigma.array()).matrix().squaredNorm();
            const float w = std::exp(-0.5f * d2);
            sum += w * x[i];
            weight_sum += w;
        }
        if (weight_sum < 1e-12f) break;
        const Vec3f next = sum / weight_sum;
        const bool converged = (next - mu).norm() < 1e-5f;
        mu = next;
        if (converged) break;
    }
    std::size_t kept = 0;
    std::size_t closest = 0;
    float closest_d2 = std::numeric_limits<float>::infinity();
    const float max_d2 = static_cast<float>(options.max_distance * options.max_distance);
    for (std::size_t i = 0; i < n; ++i) {
        const float d2 = ((x[i] - mu).array() / sigma.array()).matrix().squaredNorm();
        keep[i] = d2 <= max_d2;
        kept += keep[i];
        if (d2 < closest_d2) {
            closest_d2 = d2;
            closest = i;
        }
    }
    if (kept == 0) keep[closest] = 1;
    return keep;
}

std::size_t applyPhotoConsistency(const Visibility& vis, const std::vector<ObservationStats>& stats,
                                  const PhotoConsistencyOptions& options, std::vector<char>& keep) {
    std::atomic<std::size_t> rejected{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vis.numFaces(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<Vec3f> colors;
                          std::vector<std::uint64_t> indices;
                          std::size_t local_rejected = 0;
                          for (std::size_t f = range.begin(); f != range.end(); ++f) {
                              colors.clear();
                              indices.clear();
                              for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
                                  if (!keep[i]) continue;
                                  colors.push_back(stats[i].mean_bgr);
                                  indices.push_back(i);
                              }
                              const std::vector<char> inliers =
                                  photoConsistentViews(colors, options);
                              for (std::size_t k = 0; k < indices.size(); ++k) {
                                  if (!inliers[k]) {
                                      keep[indices[k]] = 0;
                                      ++local_rejected;
                                  }
                              }
                          }
                          rejected += local_rejected;
                      });
    return rejected;
}

}  // namespace vdbmap::texture
