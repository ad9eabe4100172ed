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
    // Coordinates as arrays, so that the loops below vectorise (RangeImage.cpp is compiled
    // without errno and traps: libvdbmap/CMakeLists.txt).
    const std::size_t n = points_L.size();
    thread_local std::vector<float> xs, ys, zs, elevation, range;
    thread_local std::vector<std::int32_t> pixel;
    xs.resize(n), ys.resize(n), zs.resize(n), elevation.resize(n), range.resize(n), pixel.resize(n);
    for (std::size_t i = 0; i < n; ++i) xs[i] = points_L[i].x(), ys[i] = points_L[i].y(), zs[i] = points_L[i].z();
    const float* x = xs.data();
    const float* y = ys.data();
    const float* z = zs.data();
    // Elevations first: the rows span the scan's own (a 26 deg HDL-64 scan: 132 rows). 100 at
    // the origin (no direction).
    float* el = elevation.data();
    for (std::size_t i = 0; i < n; ++i) {
        const float xy = std::sqrt(x[i] * x[i] + y[i] * y[i]);
        const float e = detail::fastAtan2Select(z[i], xy);
        el[i] = (xy == 0.0f) & (z[i] == 0.0f) ? 100.0f : e;
    }
    float el_min = 10.0f, el_max = -10.0f;
    for (std::size_t i = 0; i < n; ++i) {
        if (el[i] > 10.0f) continue;
        el_min = std::min(el_min, el[i]);
        el_max = std::max(el_max, el[i]);
    }
    if (el_min > el_max) return;  // no point with a direction: no rows
    elevation_min_rad_ = el_min;
    rows_ = static_cast<int>(std::floor((el_max - el_min) * inv_el_res_)) + 1;
    // Each point's pixel and range, then the least range per pixel.
    const float inv_el = inv_el_res_, inv_az = inv_az_res_;
    const int rows = rows_, cols = cols_;
    std::int32_t* px = pixel.data();
    float* rg = range.data();
    for (std::size_t i = 0; i < n; ++i) {
        const int row_i = static_cast<int>((el[i] - el_min) * inv_el);
        const int row = row_i < rows - 1 ? row_i : rows - 1;
        // column(): floor by truncation, corrected below zero.
        const float c_f = (detail::fastAtan2Select(y[i], x[i]) + 3.14159265358979323846f) * inv_az;
        int c = static_cast<int>(c_f);
        c -= c_f < static_cast<float>(c) ? 1 : 0;
        c += c < 0 ? cols : 0;
        c -= c >= cols ? cols : 0;
        px[i] = el[i] > 10.0f ? -1 : row * cols + c;
        rg[i] = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]);
    }
    range_.assign(static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_), kNoReturn);
    for (std::size_t i = 0; i < n; ++i) {
        if (px[i] < 0) continue;
        float& r = range_[static_cast<std::size_t>(px[i])];
        r = std::min(r, rg[i]);
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
            const float* __restrict row = &range_[index(r, 0)];
            float* __restrict out = &vertical[index(r, 0)];
            float* __restrict lr = last_range.data();
            int* __restrict lrow = last_row.data();
            for (std::size_t c = 0; c < cols; ++c) {
                const float rc = row[c], l = lr[c], o0 = out[c];
                const int lrw = lrow[c];
                const float near = sign * (r - lrw) <= search ? l : kNoReturn;
                const float o = o0 < rc ? o0 : rc;
                out[c] = near < o ? near : o;
                const int hit = rc != kNoReturn ? -1 : 0;  // a mask: GCC vectorises these selects
                lr[c] = hit ? rc : l;
                lrow[c] = (r & hit) | (lrw & ~hit);
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

void RangeImage::pixelsOf(const float* x, const float* y, const float* z, std::size_t n, std::int32_t* pixel,
                          float* range_m) const {
    if (rows_ == 0) {
        for (std::size_t i = 0; i < n; ++i) {
            pixel[i] = -1;
            range_m[i] = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]);
        }
        return;
    }
    const float el_min = elevation_min_rad_, inv_el = inv_el_res_, inv_az = inv_az_res_;
    const float rows_f = static_cast<float>(rows_);
    const int cols = cols_;
    for (std::size_t i = 0; i < n; ++i) {
        const float xy2 = x[i] * x[i] + y[i] * y[i];
        const float range = std::sqrt(xy2 + z[i] * z[i]);
        range_m[i] = range;
        const float row_f = (detail::fastAtan2Select(z[i], std::sqrt(xy2)) - el_min) * inv_el;
        const bool inside = (range != 0.0f) & (row_f >= 0.0f) & (row_f < rows_f);  // no branch
        const int row = static_cast<int>(inside ? row_f : 0.0f);
        // column(): floor by truncation, corrected below zero.
        const float c_f = (detail::fastAtan2Select(y[i], x[i]) + 3.14159265358979323846f) * inv_az;
        int c = static_cast<int>(c_f);
        c -= c_f < static_cast<float>(c) ? 1 : 0;
        c += c < 0 ? cols : 0;
        c -= c >= cols ? cols : 0;
        pixel[i] = inside ? row * cols + c : -1;
    }
}

}  // namespace vdbmap
