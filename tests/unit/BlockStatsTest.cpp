// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <random>

#include "vdbmap/map/BlockStats.h"

using namespace vdbmap;

namespace {

std::vector<Vec3d> randomPoints(std::mt19937& rng, std::size_t n, const Vec3d& scale) {
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<Vec3d> pts(n);
    for (auto& p : pts) p = Vec3d(g(rng) * scale.x() + 1.0, g(rng) * scale.y() - 2.0, g(rng) * scale.z() + 3.0);
    return pts;
}

}  // namespace

TEST_CASE("Eq. (1) merge equals the batch statistics for random splits", "[tsdf][stats]") {
    std::mt19937 rng(42);
    for (int trial = 0; trial < 50; ++trial) {
        const std::size_t n = 2 + rng() % 200;
        const auto pts = randomPoints(rng, n, Vec3d(0.3, 1.0, 0.05));
        const BlockStats batch = batchStats(pts);
        // Split into up to 6 consecutive chunks (some of size 1) and merge them in order.
        BlockStats merged;
        std::size_t start = 0;
        while (start < n) {
            const std::size_t len = std::min<std::size_t>(n - start, 1 + rng() % (n / 3 + 1));
            std::vector<Vec3d> part(pts.begin() + static_cast<long>(start),
                                    pts.begin() + static_cast<long>(start + len));
            merged = mergeStats(merged, batchStats(part));
            start += len;
        }
        REQUIRE(merged.n == Approx(batch.n));
        REQUIRE((merged.mean - batch.mean).norm() < 1e-12);
        REQUIRE((merged.cov - batch.cov).norm() < 1e-10 * (1.0 + batch.cov.norm()));
    }
}

TEST_CASE("One point has its position as mean and zero covariance", "[tsdf][stats]") {
    const BlockStats s = batchStats({Vec3d(1, 2, 3)});
    CHECK(s.n == 1.0);
    CHECK(s.mean == Vec3d(1, 2, 3));
    CHECK(s.cov.isZero());
    const BlockStats m = mergeStats(BlockStats{}, s);
    CHECK(m.mean == s.mean);
}

TEST_CASE("PCA normal of a plane is oriented towards the sensor", "[tsdf][stats]") {
    // Points on the plane z = 0.5 (spread in x, y).
    std::vector<Vec3d> pts;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) pts.emplace_back(0.07 * i, 0.05 * j, 0.5);
    const BlockStats s = batchStats(pts);
    const PlaneEstimate above = estimatePlane(s, Vec3d(0, 0, 10), 5);
    REQUIRE(above.valid);
    CHECK(above.normal.z() == Approx(1.0).margin(1e-9));
    CHECK(above.flatness == Approx(1.0).margin(1e-9));
    const PlaneEstimate below = estimatePlane(s, Vec3d(3, -2, -10), 5);
    REQUIRE(below.valid);
    CHECK(below.normal.z() == Approx(-1.0).margin(1e-9));
}

TEST_CASE("Flatness: a thick cloud is less flat than a thin one", "[tsdf][stats]") {
    std::mt19937 rng(7);
    const auto thin = batchStats(randomPoints(rng, 500, Vec3d(0.2, 0.2, 0.005)));
    const auto thick = batchStats(randomPoints(rng, 500, Vec3d(0.2, 0.2, 0.15)));
    const auto p_thin = estimatePlane(thin, Vec3d(0, 0, 10), 5);
    const auto p_thick = estimatePlane(thick, Vec3d(0, 0, 10), 5);
    REQUIRE(p_thin.valid);
    REQUIRE(p_thick.valid);
    CHECK(p_thin.flatness > 0.99);
    CHECK(p_thick.flatness < p_thin.flatness);
    // Eq. (3) from the eigenvalues.
    CHECK(p_thick.flatness == Approx(1.0 - p_thick.eigenvalues.z() / p_thick.eigenvalues.y()));
}

TEST_CASE("Degenerate blocks: too few, collinear and identical points", "[tsdf][stats]") {
    const Vec3d sensor(0, 0, 10);
    std::vector<Vec3d> few = {Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(1, 1, 0.1)};
    CHECK_FALSE(estimatePlane(batchStats(few), sensor, 5).valid);
    std::vector<Vec3d> line;
    for (int i = 0; i < 20; ++i) line.emplace_back(0.1 * i, 0.2 * i, -0.05 * i);
    const PlaneEstimate pl = estimatePlane(batchStats(line), sensor, 5);
    CHECK_FALSE(pl.valid);
    CHECK(pl.normal.isZero());
    std::vector<Vec3d> same(20, Vec3d(1, 1, 1));
    CHECK_FALSE(estimatePlane(batchStats(same), sensor, 5).valid);
}

TEST_CASE("BlockStatsGrid: one entry per block, found by block coordinate", "[tsdf][stats]") {
    BlockStatsGrid grid;
    CHECK(grid.find(openvdb::Coord(0, 0, 0)) == -1);
    const auto a = grid.findOrCreate(BlockStatsGrid::blockOf(openvdb::Coord(-1, 7, 8)));
    const auto b = grid.findOrCreate(BlockStatsGrid::blockOf(openvdb::Coord(-8, 0, 15)));
    CHECK(a == b);  // both in block (-1, 0, 1)
    CHECK(grid.blockCoord(a) == openvdb::Coord(-1, 0, 1));
    const auto c = grid.findOrCreate(openvdb::Coord(5, 5, 5));
    CHECK(c != a);
    CHECK(grid.size() == 2);
    CHECK(grid.bytesPerBlock() >= static_cast<double>(sizeof(BlockEntry)));
}

TEST_CASE("The integrator's indexed one-pass batch statistics equal batchStats", "[tsdf][stats]") {
    // Points of one 0.8 m block 1 km from the origin, taken through an index (a permutation
    // with repeats left out), as the integrator takes a block's points of one scan.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 0.8f);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<Vec3f> points(1 + rng() % 300);
        for (auto& p : points) p = Vec3f(1000.0f + u(rng), -700.0f + u(rng), 12.0f + 0.05f * u(rng));
        std::vector<std::uint32_t> index;
        std::vector<Vec3d> picked;
        for (std::uint32_t i = 0; i < points.size(); ++i)
            if (rng() % 3 != 0 || i == 0) {
                index.push_back(i);
                picked.push_back(points[i].cast<double>());
            }
        const BlockStats expected = batchStats(picked);
        const BlockStats got = batchStatsIndexed(points.data(), index.data(), index.size());
        REQUIRE(got.n == expected.n);
        REQUIRE((got.mean - expected.mean).norm() < 1e-9);
        REQUIRE((got.cov - expected.cov).norm() < 1e-9 * (1.0 + expected.cov.norm()));
        if (index.size() == 1) CHECK(got.cov.norm() == 0.0);
    }
    CHECK(batchStatsIndexed(nullptr, nullptr, 0).n == 0.0);
}
