// SPDX-License-Identifier: Apache-2.0
// Phase 1 of the integrator classifies points a batch at a time (map/PointCells.h): four at once
// with SSE2, the rest one by one. The batch must give exactly what the one-point reference
// gives (the same status, the same cell bits), and the reference's cell must be the voxel that
// the rest of the integrator computes (voxelOf), or its half-voxel cell.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "map/PointCells.h"
#include "map/RayUpdate.h"

using namespace vdbmap;
using namespace vdbmap::detail;

namespace {

PointLimits limits() {
    PointLimits lim;
    lim.origin_W = Vec3f(3.25f, -1.5f, 1.73f);
    lim.min_range2 = 0.5f * 0.5f;
    lim.max_range2 = 80.0f * 80.0f;
    lim.inv_voxel = 1.0f / 0.1f;
    lim.max_index = 1e9f;
    return lim;
}

/// Random points around the origin and at cell boundaries, and every kind of dropped point.
std::vector<Vec3f> testPoints() {
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<Vec3f> pts;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> near(-90.0f, 90.0f);
    for (int i = 0; i < 4000; ++i) pts.emplace_back(near(rng), near(rng), near(rng) * 0.1f);
    // On and next to the cell boundaries (x / voxel + 1/2 an integer or a half), both signs.
    std::uniform_int_distribution<int> k(-400, 400);
    for (int i = 0; i < 4000; ++i) {
        float x = (static_cast<float>(k(rng)) - 0.5f) * 0.1f, y = static_cast<float>(k(rng)) * 0.05f;
        const int nudge = i % 3;
        if (nudge == 1) x = std::nextafter(x, inf);
        if (nudge == 2) y = std::nextafter(y, -inf);
        pts.emplace_back(x, y, -0.05f);
    }
    // Exactly on the boundaries: m / 4 m is an exact float, and so are m / 4 * 10 + 1/2 and
    // twice it (floor of an exact integer).
    for (int m = -100; m <= 100; ++m)
        pts.emplace_back(0.25f * static_cast<float>(m), 0.25f * static_cast<float>(100 - m), -1.0f);
    const Vec3f o = limits().origin_W;
    // Next to the range bounds where the order of the sum of squares decides the status:
    // Eigen's squaredNorm adds x^2 + (y^2 + z^2), which phase 1 must keep.
    const auto straddles = [](const Vec3f& d, float bound2) {
        const float eigen = d.squaredNorm(), left = (d.x() * d.x() + d.y() * d.y()) + d.z() * d.z();
        return (eigen > bound2) != (left > bound2) || (eigen < bound2) != (left < bound2);
    };
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    int found = 0;
    for (int i = 0; i < 2000000 && found < 20; ++i) {
        const Vec3f dir = Vec3f(unit(rng), unit(rng), unit(rng)).normalized();
        for (const float r : {80.0f, 0.5f}) {
            Vec3f d = dir * r;
            for (int step = 0; step < 4; ++step, d.x() = std::nextafter(d.x(), 1e9f)) {
                const Vec3f q = o + d;
                if (straddles(q - o, r * r)) {
                    pts.push_back(q);
                    ++found;
                }
            }
        }
    }
    REQUIRE(found >= 20);
    const std::vector<Vec3f> special = {
        {nan, 0.0f, 0.0f}, {0.0f, nan, 0.0f}, {0.0f, 0.0f, nan}, {inf, 0.0f, 0.0f},
        {0.0f, -inf, 0.0f}, {0.0f, 0.0f, inf}, {nan, inf, -inf},
        o, o + Vec3f(0.49f, 0.0f, 0.0f), o + Vec3f(0.0f, 0.5f, 0.0f),           // at the origin, on min
        o + Vec3f(80.0f, 0.0f, 0.0f), o + Vec3f(0.0f, 0.0f, -80.01f),          // on max, beyond it
        {-0.0f, -0.0f, -0.0f}, {2e8f, 0.0f, 0.0f}, {-1e30f, 0.0f, 0.0f}, {3e38f, 3e38f, 3e38f}};
    for (const Vec3f& p : special) pts.push_back(p);
    return pts;
}

/// Returns how many points got each status.
template <int kDivisions>
std::array<std::size_t, 4> checkBatches(const std::vector<Vec3f>& pts, PointLimits lim) {
    std::array<std::size_t, 4> count{};
    // Batches of every size up to the capacity and every offset modulo 4, so the remainder
    // path and the four-at-once path both see every kind of point.
    for (std::size_t first = 0, size = 1; first < pts.size();
         first += size, size = size % PointCells::kCapacity + 1) {
        const std::size_t n = std::min(size, pts.size() - first);
        PointCells batch;
        classifyPoints<kDivisions>(pts.data() + first, n, lim, batch);
        for (std::size_t j = 0; j < n; ++j) {
            const Vec3f& p = pts[first + j];
            std::int32_t cell[3] = {0, 0, 0};
            const std::int32_t status = classifyPoint<kDivisions>(p, lim, cell);
            INFO("point " << p.transpose() << ", batch of " << n << " at " << first);
            REQUIRE(batch.status[j] == status);
            ++count[static_cast<std::size_t>(status)];
            if (status != kValid) continue;
            REQUIRE(batch.x[j] == cell[0]);
            REQUIRE(batch.y[j] == cell[1]);
            REQUIRE(batch.z[j] == cell[2]);
        }
    }
    return count;
}

}  // namespace

TEST_CASE("Phase 1's batches of points classify as the one-point reference, bit for bit",
          "[tsdf][integrator]") {
    const std::vector<Vec3f> pts = testPoints();
    const auto count = checkBatches<1>(pts, limits());
    // Every status occurs: 7 non-finite points, 2 at the origin, the random ones beyond 80 m.
    CHECK(count[kNonFinite] == 7);
    CHECK(count[kAtOrigin] == 2);
    CHECK(count[kRange] > 500);
    CHECK(count[kValid] > 6000);
    CHECK(checkBatches<2>(pts, limits()) == count);
    PointLimits tight = limits();  // a small index range drops the far points as out of range
    tight.max_index = 300.0f;
    const auto tight_count = checkBatches<1>(pts, tight);
    CHECK(tight_count[kRange] > count[kRange]);
    // No valid range at all: at the origin still comes before out of range.
    PointLimits none = limits();
    none.max_range2 = -1.0f;
    const auto none_count = checkBatches<1>(pts, none);
    CHECK(none_count[kAtOrigin] == count[kAtOrigin]);
    CHECK(none_count[kValid] == 0);
}

TEST_CASE("The reference's statuses and cells: voxelOf, its half-voxel cells, and the drop order",
          "[tsdf][integrator]") {
    const PointLimits lim = limits();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::int32_t c[3];
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-50.0f, 50.0f);
    for (int i = 0; i < 2000; ++i) {
        const Vec3f p(u(rng), u(rng), u(rng));
        if (classifyPoint<1>(p, lim, c) != kValid) continue;
        const openvdb::Coord v = voxelOf(p, lim.inv_voxel);
        CHECK(openvdb::Coord(c[0], c[1], c[2]) == v);
        REQUIRE(classifyPoint<2>(p, lim, c) == kValid);
        // A half-voxel cell lies in its voxel: floor(2 x) >> 1 == floor(x).
        CHECK(openvdb::Coord(c[0] >> 1, c[1] >> 1, c[2] >> 1) == v);
    }
    // Voxel 3 covers [2.5, 3.5) voxels; its half cells are 6 = [2.5, 3) and 7 = [3, 3.5).
    REQUIRE(classifyPoint<2>(Vec3f(0.29f, 10.0f, 0.0f), lim, c) == kValid);
    CHECK(c[0] == 6);
    REQUIRE(classifyPoint<2>(Vec3f(0.31f, 10.0f, 0.0f), lim, c) == kValid);
    CHECK(c[0] == 7);
    // A non-finite point is non-finite first, even at the origin; at the origin before range.
    CHECK(classifyPoint<1>(Vec3f(nan, lim.origin_W.y(), lim.origin_W.z()), lim, c) == kNonFinite);
    CHECK(classifyPoint<1>(lim.origin_W, lim, c) == kAtOrigin);
    PointLimits no_range = lim;
    no_range.max_range2 = -1.0f;
    CHECK(classifyPoint<1>(lim.origin_W, no_range, c) == kAtOrigin);
    CHECK(classifyPoint<1>(lim.origin_W + Vec3f(1.0f, 0.0f, 0.0f), no_range, c) == kRange);
}
