// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/RingSpacing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vdbmap {
namespace {

constexpr int kBins = RingSpacing::kBins;

int binOf(double sin_elev) {
    const int i = static_cast<int>((sin_elev + 1.0) * 0.5 * kBins);
    return std::clamp(i, 0, kBins - 1);
}

double binCentre(int i) { return (i + 0.5) * 2.0 / kBins - 1.0; }

/// The elevation of each bin's centre, asin(binCentre(i)): computed once (the table is 64 kB;
/// 8192 arcsines per scan were most of fromElevations' time).
const std::vector<double>& binElevations() {
    static const std::vector<double> theta = [] {
        std::vector<double> t(kBins);
        for (int i = 0; i < kBins; ++i) t[static_cast<std::size_t>(i)] = std::asin(binCentre(i));
        return t;
    }();
    return theta;
}

/// The widest run of bins one ring may cover: 0.3 deg near the horizon (~0.014 deg per bin);
/// the closest rings of a VLS-128 are 0.11 deg apart, an HDL-64's 0.33 deg.
constexpr int kMaxRingBins = 21;

}  // namespace

RingSpacing RingSpacing::fromElevations(std::vector<double> elevations_rad) {
    RingSpacing rs;
    std::sort(elevations_rad.begin(), elevations_rad.end());
    elevations_rad.erase(std::unique(elevations_rad.begin(), elevations_rad.end()), elevations_rad.end());
    const std::size_t k = elevations_rad.size();
    if (k < 3) return rs;
    rs.rings_ = k;
    // The gap of ring j towards the horizon: to j + 1 below it (negative elevation), to j - 1
    // above it; 0 for the outermost ring on that side.
    std::vector<float> gap(k, 0.0f);
    for (std::size_t j = 0; j < k; ++j) {
        if (elevations_rad[j] < 0.0 && j + 1 < k)
            gap[j] = static_cast<float>(std::min(elevations_rad[j + 1], 0.0) - elevations_rad[j]);
        else if (elevations_rad[j] >= 0.0 && j > 0)
            gap[j] = static_cast<float>(elevations_rad[j] - std::max(elevations_rad[j - 1], 0.0));
    }
    // Each bin takes the gap of the ring nearest to it (rings are sorted: one sweep).
    rs.gap_rad_.resize(kBins);
    const std::vector<double>& bin_theta = binElevations();
    std::size_t j = 0;
    for (int i = 0; i < kBins; ++i) {
        const double theta = bin_theta[static_cast<std::size_t>(i)];
        while (j + 1 < k && std::abs(elevations_rad[j + 1] - theta) <= std::abs(elevations_rad[j] - theta)) ++j;
        rs.gap_rad_[static_cast<std::size_t>(i)] = gap[j];
    }
    return rs;
}

RingSpacing RingSpacing::estimate(PointSpan points_L, std::size_t stride) {
    // Phase 1: histogram of sin(elevation) of every stride-th point.
    std::vector<std::uint32_t> count(kBins, 0);
    std::vector<double> sum(kBins, 0.0);
    stride = std::max<std::size_t>(stride, 1);
    // Successive points mostly fall in the same bin (one ring): its count and sum stay in
    // registers until the bin changes (the sum's additions in the same order).
    std::size_t bin = 0;
    std::uint32_t bin_count = 0;
    double bin_sum = 0.0;
    for (std::size_t i = 0; i < points_L.size(); i += stride) {
        const Vec3f& p = points_L[i];
        const float r2 = p.squaredNorm();
        if (!(r2 > 1e-6f) || !std::isfinite(r2)) continue;
        const double s = p.z() / std::sqrt(static_cast<double>(r2));
        const std::size_t b = static_cast<std::size_t>(binOf(s));
        if (b != bin) {
            count[bin] = bin_count;
            sum[bin] = bin_sum;
            bin = b;
            bin_count = count[b];
            bin_sum = sum[b];
        }
        ++bin_count;
        bin_sum += s;
    }
    count[bin] = bin_count;
    sum[bin] = bin_sum;
    // Phase 2: rings = runs of occupied bins (a single empty bin does not end a run); a bin
    // holding a lone point between rings (a mixed pixel, a reflection) does not count. A run
    // wider than kMaxRingBins is no ring: a sensor whose beams do not leave the origin (a
    // real HDL-64's lasers sit up to 0.2 m from it, so a laser's elevation seen from the origin
    // changes with range) or no spinning sensor at all. If such runs hold more than a fifth of
    // the points, the scan has no usable rings.
    std::vector<double> elevations;
    std::uint64_t n = 0, in_rings = 0, smeared = 0;
    int first_bin = 0, last_bin = 0;
    double s_sum = 0.0;
    int empty_run = 0;
    auto close = [&]() {
        if (n > 0 && last_bin - first_bin < kMaxRingBins) {
            elevations.push_back(std::asin(s_sum / static_cast<double>(n)));
            in_rings += n;
        } else {
            smeared += n;
        }
        n = 0;
        s_sum = 0.0;
    };
    for (int i = 0; i < kBins; ++i) {
        const std::size_t b = static_cast<std::size_t>(i);
        if (count[b] >= 2) {
            if (n == 0) first_bin = i;
            last_bin = i;
            n += count[b];
            s_sum += sum[b];
            empty_run = 0;
        } else if (++empty_run > 1) {
            close();
        }
    }
    close();
    if (smeared * 5 > in_rings + smeared) return RingSpacing{};
    // Rings are lines with empty space between them: between the lowest and the highest
    // occupied bin, at most half the bins may hold a point (an HDL-64: ~7 %; points spread over
    // all elevations: ~all of them).
    int lo = kBins, hi = -1, occupied = 0;
    for (int i = 0; i < kBins; ++i) {
        if (count[static_cast<std::size_t>(i)] == 0) continue;
        lo = std::min(lo, i);
        hi = i;
        ++occupied;
    }
    if (hi < lo || 2 * occupied > hi - lo + 1) return RingSpacing{};
    return fromElevations(std::move(elevations));
}

}  // namespace vdbmap
