// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

namespace detail {

/// atan2 within 1e-5 rad (0.0006 deg, far below a pixel), without the library call's cost:
/// octant reduction and a degree-9 odd minimax polynomial of atan on [0, 1]. Inline: the vote
/// loops call it twice per look-up.
inline float fastAtan2(float y, float x) {
    const float ax = std::fabs(x), ay = std::fabs(y);
    const float mx = std::max(ax, ay), mn = std::min(ax, ay);
    if (mx == 0.0f) return 0.0f;
    const float a = mn / mx;
    const float s = a * a;
    float r = ((((-0.0117212f * s + 0.05265332f) * s - 0.11643287f) * s + 0.19354346f) * s -
               0.33262347f) * s * a + 0.99997726f * a;
    if (ay > ax) r = 1.57079637f - r;
    if (x < 0.0f) r = 3.14159274f - r;
    return y < 0.0f ? -r : r;
}

/// fastAtan2 with selects instead of branches (the same result, 0 at the origin), for loops
/// the compiler vectorises.
inline float fastAtan2Select(float y, float x) {
    const float ax = std::fabs(x), ay = std::fabs(y);
    const float mx = ax < ay ? ay : ax, mn = ay < ax ? ay : ax;
    const float a = mn / mx;
    const float s = a * a;
    float r = ((((-0.0117212f * s + 0.05265332f) * s - 0.11643287f) * s + 0.19354346f) * s -
               0.33262347f) * s * a + 0.99997726f * a;
    r = ay > ax ? 1.57079637f - r : r;
    r = x < 0.0f ? 3.14159274f - r : r;
    r = y < 0.0f ? -r : r;
    return mx == 0.0f ? 0.0f : r;
}

}  // namespace detail

/// Pixel size and neighbourhood of a RangeImage (docs/dynamic.md).
struct RangeImageConfig {
    double azimuth_res_deg = 0.2;    ///< column width; about a spinning LiDAR's azimuth step
    double elevation_res_deg = 0.2;  ///< row height; finer than the ring spacing (rows between rings are empty)
    int azimuth_radius_px = 1;       ///< columns on each side taken into a pixel's bracket
    /// How far (rows) to look below and above a pixel for the nearest row holding a return.
    int elevation_search_px = 8;
};

/// A spinning LiDAR's scan as a spherical range image in its own sensor frame L (x forward, y
/// left, z up; azimuth atan2(y, x), elevation atan2(z, |xy|)), for free-space tests: did this
/// scan see through a point?
///
/// The test does not read a pixel alone. A point between two rings of this scan falls in an
/// empty row or in one ring's row; on the ground at grazing incidence the ring above it lands
/// behind the point and the ring below in front. So each pixel stores its *bracket range*: the
/// least range over the columns within azimuth_radius_px of it, of the nearest non-empty row
/// below it (within elevation_search_px), its own row and the nearest non-empty row above it.
/// A point seen through by every ring bracketing it really lies in free space; a point on a
/// surface this scan saw at grazing incidence always has a bracketing ring in front of it (the
/// lower one). Min over neighbours = the erosion of free space of Removert's multi-resolution
/// range images and of DUFOMap's void dilation (docs/dynamic.md).
class RangeImage {
public:
    static constexpr float kNoReturn = std::numeric_limits<float>::infinity();
    /// The direction is outside the image's rows (or the image is empty): no evidence.
    static constexpr float kOutside = -1.0f;

    RangeImage() = default;
    /// The image of `points_L` (a scan in its sensor frame; points at the origin are ignored).
    /// The rows span the scan's elevations (no rows for an empty scan).
    RangeImage(const std::vector<Vec3f>& points_L, const RangeImageConfig& config);

    /// The bracket range (metres) of the pixel holding the direction of `p_L` (LiDAR frame),
    /// kNoReturn if no return brackets it (every row nearby empty: the sky, or nothing within
    /// the sensor's range), kOutside if the direction is outside the rows; `range_m` gets |p_L|.
    float bracketRange(const Vec3f& p_L, float& range_m) const {
        const float xy2 = p_L.x() * p_L.x() + p_L.y() * p_L.y();
        range_m = std::sqrt(xy2 + p_L.z() * p_L.z());
        if (rows_ == 0 || range_m == 0.0f) return kOutside;
        const float row_f = (detail::fastAtan2(p_L.z(), std::sqrt(xy2)) - elevation_min_rad_) * inv_el_res_;
        if (!(row_f >= 0.0f) || row_f >= static_cast<float>(rows_)) return kOutside;
        return bracket_[index(static_cast<int>(row_f), column(detail::fastAtan2(p_L.y(), p_L.x())))];
    }

    /// bracketRange for a block of n points given by coordinates (x, y, z in the LiDAR frame,
    /// one array each): pixel[i] is the pixel holding p_i's direction, or -1 where
    /// bracketRange returns kOutside; range_m[i] = |p_i|. The same arithmetic as bracketRange,
    /// written branch-free so that the compiler vectorises it (the vote loops' look-ups).
    void pixelsOf(const float* x, const float* y, const float* z, std::size_t n, std::int32_t* pixel,
                  float* range_m) const;
    /// The bracket range of a pixel from pixelsOf (>= 0).
    float bracketAt(std::int32_t pixel) const { return bracket_[static_cast<std::size_t>(pixel)]; }

    int rows() const { return rows_; }
    int cols() const { return cols_; }
    std::size_t memoryBytes() const { return bracket_.capacity() * sizeof(float); }

private:
    std::size_t index(int row, int col) const {
        return static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(col);
    }
    int column(float azimuth_rad) const {
        int c = static_cast<int>(std::floor((azimuth_rad + 3.14159265358979323846f) * inv_az_res_));
        if (c < 0) c += cols_;
        if (c >= cols_) c -= cols_;
        return c;
    }
    void computeBrackets(const RangeImageConfig& config);

    int rows_ = 0, cols_ = 0;
    float elevation_min_rad_ = 0.0f;
    float inv_az_res_ = 1.0f, inv_el_res_ = 1.0f;  ///< pixels per radian
    std::vector<float> range_;    ///< least range per pixel, rows of cols_ (freed once bracketed)
    std::vector<float> bracket_;  ///< bracket range per pixel
};

}  // namespace vdbmap
