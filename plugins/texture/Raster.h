// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace vdbmap::texture {

/// Calls `span(y, x_begin, x_end)` (x_end exclusive) for every image row y whose pixel centres
/// inside the triangle `pixels` (docs/DATA.md pixel convention: (0,0) is the centre of the top-left
/// pixel) form a non-empty run, clipped to [0, width) x [0, height). Returns the number of
/// covered pixels. A triangle that covers no pixel centre yields nothing (callers fall back to
/// the pixel nearest to the centroid).
template <typename SpanFn>
long rasterizeSpans(const std::array<Eigen::Vector2f, 3>& pixels, int width, int height,
                    SpanFn&& span) {
    const float y_min = std::min({pixels[0].y(), pixels[1].y(), pixels[2].y()});
    const float y_max = std::max({pixels[0].y(), pixels[1].y(), pixels[2].y()});
    const int row_begin = std::max(0, static_cast<int>(std::ceil(y_min)));
    const int row_end = std::min(height - 1, static_cast<int>(std::floor(y_max)));
    long covered = 0;
    for (int y = row_begin; y <= row_end; ++y) {
        const float yc = static_cast<float>(y);
        float x_lo = std::numeric_limits<float>::infinity();
        float x_hi = -std::numeric_limits<float>::infinity();
        for (int e = 0; e < 3; ++e) {
            const Eigen::Vector2f& a = pixels[e];
            const Eigen::Vector2f& b = pixels[(e + 1) % 3];
            if ((a.y() <= yc && b.y() >= yc) || (b.y() <= yc && a.y() >= yc)) {
                const float dy = b.y() - a.y();
                if (std::abs(dy) < 1e-12f) {
                    x_lo = std::min({x_lo, a.x(), b.x()});
                    x_hi = std::max({x_hi, a.x(), b.x()});
                } else {
                    const float x = a.x() + (yc - a.y()) * (b.x() - a.x()) / dy;
                    x_lo = std::min(x_lo, x);
                    x_hi = std::max(x_hi, x);
                }
            }
        }
        if (!(x_lo <= x_hi)) continue;
        const int x_begin = std::max(0, static_cast<int>(std::ceil(x_lo - 1e-4f)));
        const int x_end = std::min(width, static_cast<int>(std::floor(x_hi + 1e-4f)) + 1);
        if (x_begin < x_end) {
            span(y, x_begin, x_end);
            covered += x_end - x_begin;
        }
    }
    return covered;
}

/// Barycentric coordinates of `p` in the triangle `pixels` (w0, w1, w2; sum 1). Degenerate
/// triangles give (1/3, 1/3, 1/3).
inline Eigen::Vector3f barycentric(const std::array<Eigen::Vector2f, 3>& pixels,
                                   const Eigen::Vector2f& p) {
    const Eigen::Vector2f e1 = pixels[1] - pixels[0];
    const Eigen::Vector2f e2 = pixels[2] - pixels[0];
    const Eigen::Vector2f d = p - pixels[0];
    const float det = e1.x() * e2.y() - e1.y() * e2.x();
    if (std::abs(det) < 1e-12f) return Eigen::Vector3f::Constant(1.0f / 3.0f);
    const float w1 = (d.x() * e2.y() - d.y() * e2.x()) / det;
    const float w2 = (e1.x() * d.y() - e1.y() * d.x()) / det;
    return {1.0f - w1 - w2, w1, w2};
}

}  // namespace vdbmap::texture
