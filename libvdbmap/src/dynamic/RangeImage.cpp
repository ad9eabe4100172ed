// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/RangeImage.h"

#include <algorithm>
#include <cmath>

namespace vdbmap {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// atan2 within 1e-5 rad (0.0006 deg, far below a pixel), without the library call's cost:
/// octant reduction and a degree-9 odd minimax polynomial of atan on [0, 1].
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

}  // namespace

int RangeImage::column(float azimuth_rad) const {
    int c = static_cast<int>(std::floor((azimuth_rad + static_cast<float>(kPi)) * inv_az_res_));
    if (c < 0) c += cols_;
    if (c >= cols_) c -= cols_;
    return c;
}

RangeImage::RangeImage(const std::vector<Vec3f>& points_L, const RangeImageConfig& config) {
    const double az_res = config.azimuth_res_deg * kPi / 180.0;
    const double el_res = config.elevation_res_deg * kPi / 180.0;
    inv_az_res_ = static_cast<float>(1.0 / az_res);
    inv_el_res_ = static_cast<float>(1.0 / el_res);
    cols_ = std::max(1, static_cast<int>(std::ceil(2.0 * kPi / az_res)));
    // Elevations first: the rows span the scan's own (a 26 deg HDL-64 scan: 132 rows).
    thread_local std::vector<float> elevation;
    elevation.resize(points_L.size());
    float el_min = 10.0f, el_max = -10.0f;
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        const Vec3f& p = points_L[i];
        const float xy = std::sqrt(p.x() * p.x() + p.y() * p.y());
        if (xy == 0.0f && p.z() == 0.0f) {
            elevation[i] = 100.0f;  // at the origin: no direction
            continue;
        }
        elevation[i] = fastAtan2(p.z(), xy);
        el_min = std::min(el_min, elevation[i]);
        el_max = std::max(el_max, elevation[i]);
    }
    if (el_min > el_max) return;  // no point with a direction: no rows
    elevation_min_rad_ = el_min;
    rows_ = static_cast<int>(std::floor((el_max - el_min) * inv_el_res_)) + 1;
    range_.assign(static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_), kNoReturn);
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        if (elevation[i] > 10.0f) continue;
        const Vec3f& p = points_L[i];
        const int row = std::min(rows_ - 1, static_cast<int>((elevation[i] - el_min) * inv_el_res_));
        const int col = column(fastAtan2(p.y(), p.x()));
        float& r = range_[index(row, col)];
        r = std::min(r, p.norm());
    }
    computeBrackets(config);
    range_ = std::vector<float>();  // the brackets are all a test reads
}

void RangeImage::computeBrackets(const RangeImageConfig& config) {
    // Per column: the least range over the nearest non-empty row below, the row itself and the
    // nearest non-empty row above; then the least of those over the neighbouring columns. Row
    // by row (the image is row-major), keeping per column the last non-empty row seen.
    const int search = std::max(0, config.elevation_search_px);
    const std::size_t cols = static_cast<std::size_t>(cols_);
    thread_local std::vector<float> vertical;
    thread_local std::vector<float> last_range;
    thread_local std::vector<int> last_row;
    vertical.assign(range_.size(), kNoReturn);
    for (int pass = 0; pass < 2; ++pass) {  // 0: rows below (going up), 1: rows above (going down)
        last_range.assign(cols, kNoReturn);
        last_row.assign(cols, -(1 << 20));
        for (int k = 0; k < rows_; ++k) {
            const int r = pass == 0 ? k : rows_ - 1 - k;
            const float* row = &range_[index(r, 0)];
            float* out = &vertical[index(r, 0)];
            for (std::size_t c = 0; c < cols; ++c) {
                float v = std::min(out[c], row[c]);
                if (std::abs(r - last_row[c]) <= search) v = std::min(v, last_range[c]);
                out[c] = v;
                if (row[c] != kNoReturn) {
                    last_range[c] = row[c];
                    last_row[c] = r;
                }
            }
        }
    }
    const int radius = std::max(0, std::min(config.azimuth_radius_px, cols_ / 2));
    bracket_.resize(range_.size());
    for (int r = 0; r < rows_; ++r) {
        const float* in = &vertical[index(r, 0)];
        float* out = &bracket_[index(r, 0)];
        for (int c = 0; c < cols_; ++c) {
            float v = kNoReturn;
            for (int dc = -radius; dc <= radius; ++dc) {
                int cc = c + dc;
                if (cc < 0) cc += cols_;
                if (cc >= cols_) cc -= cols_;
                v = std::min(v, in[cc]);
            }
            out[c] = v;
        }
    }
}

float RangeImage::bracketRange(const Vec3f& p_L, float& range_m) const {
    const float xy2 = p_L.x() * p_L.x() + p_L.y() * p_L.y();
    range_m = std::sqrt(xy2 + p_L.z() * p_L.z());
    if (rows_ == 0 || range_m == 0.0f) return kOutside;
    const float row_f = (fastAtan2(p_L.z(), std::sqrt(xy2)) - elevation_min_rad_) * inv_el_res_;
    if (!(row_f >= 0.0f) || row_f >= static_cast<float>(rows_)) return kOutside;
    return bracket_[index(static_cast<int>(row_f), column(fastAtan2(p_L.y(), p_L.x())))];
}

}  // namespace vdbmap
