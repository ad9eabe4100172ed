// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/RangeImage.h"

#include <algorithm>
#include <cmath>

namespace vdbmap {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

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
        elevation[i] = detail::fastAtan2(p.z(), xy);
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
        const int col = column(detail::fastAtan2(p.y(), p.x()));
        float& r = range_[index(row, col)];
        r = std::min(r, p.norm());
    }
    computeBrackets(config);
    range_ = std::vector<float>();  // the brackets are all a test reads
}

void RangeImage::computeBrackets(const RangeImageConfig& config) {
    // Per column: the least range over the nearest non-empty row below, the row itself and the
    // nearest non-empty row above; then the least of those over the neighbouring columns. Row
    // by row (the image is row-major), keeping per column the last non-empty row seen. The
    // inner loops are branch-free selects over a row, so that the compiler vectorises them.
    const int search = std::max(0, config.elevation_search_px);
    const std::size_t cols = static_cast<std::size_t>(cols_);
    thread_local std::vector<float> vertical;
    thread_local std::vector<float> last_range;
    thread_local std::vector<int> last_row;
    vertical.assign(range_.size(), kNoReturn);
    for (int pass = 0; pass < 2; ++pass) {  // 0: rows below (going up), 1: rows above (going down)
        last_range.assign(cols, kNoReturn);
        // Rows seen so far lie on one side of r: |r - last_row| is r - last_row going up and
        // last_row - r going down. "Never seen" is far enough on either side.
        last_row.assign(cols, pass == 0 ? -(1 << 20) : (1 << 20));
        const int sign = pass == 0 ? 1 : -1;
        for (int k = 0; k < rows_; ++k) {
            const int r = pass == 0 ? k : rows_ - 1 - k;
            const float* row = &range_[index(r, 0)];
            float* out = &vertical[index(r, 0)];
            float* lr = last_range.data();
            int* lrow = last_row.data();
            for (std::size_t c = 0; c < cols; ++c) {
                const float near = sign * (r - lrow[c]) <= search ? lr[c] : kNoReturn;
                out[c] = std::min(std::min(out[c], row[c]), near);
                const bool hit = row[c] != kNoReturn;
                lr[c] = hit ? row[c] : lr[c];
                lrow[c] = hit ? r : lrow[c];
            }
        }
    }
    const int radius = std::max(0, std::min(config.azimuth_radius_px, cols_ / 2));
    bracket_.resize(range_.size());
    for (int r = 0; r < rows_; ++r) {
        const float* in = &vertical[index(r, 0)];
        float* out = &bracket_[index(r, 0)];
        // Columns whose neighbourhood wraps around azimuth +-180 deg, then the others.
        auto wrapped = [&](int c) {
            float v = kNoReturn;
            for (int dc = -radius; dc <= radius; ++dc) {
                int cc = c + dc;
                if (cc < 0) cc += cols_;
                if (cc >= cols_) cc -= cols_;
                v = std::min(v, in[cc]);
            }
            out[c] = v;
        };
        for (int c = 0; c < std::min(radius, cols_); ++c) wrapped(c);
        for (int c = std::max(radius, cols_ - radius); c < cols_; ++c) wrapped(c);
        for (int dc = -radius; dc <= radius; ++dc) {
            const float* shifted = in + dc;
            if (dc == -radius) {
                for (int c = radius; c < cols_ - radius; ++c) out[c] = shifted[c];
            } else {
                for (int c = radius; c < cols_ - radius; ++c) out[c] = std::min(out[c], shifted[c]);
            }
        }
    }
}

}  // namespace vdbmap
