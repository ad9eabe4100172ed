// SPDX-License-Identifier: Apache-2.0
// The packed TSDF voxel (vdbmap/map/TsdfVoxel.h): fixed-point round trips, clamping, and the
// ranges the integrator may use.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "support/PlainAtsdfConfig.h"
#include "vdbmap/Error.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VoxelMap.h"

using namespace vdbmap;
using vdbmap::test::plainAtsdfConfig;

TEST_CASE("Packed voxels round-trip within half a quantum", "[tsdf][codec]") {
    const TsdfCodec codec(0.3f, 100.0f);
    CHECK(codec.sdfQuantum() == Approx(0.3 / 32767.0));
    CHECK(codec.weightQuantum() == Approx(100.0 / 65535.0));
    std::mt19937 rng(7);
    // Weights from one quantum up (below half a quantum a positive weight becomes one quantum,
    // see the next test).
    std::uniform_real_distribution<float> sdf(-0.3f, 0.3f), weight(codec.weightQuantum(), 100.0f);
    double max_sdf_err = 0.0, max_w_err = 0.0;
    for (int i = 0; i < 100000; ++i) {
        const float d = sdf(rng), w = weight(rng);
        const std::uint32_t v = codec.encode(d, w);
        max_sdf_err = std::max(max_sdf_err, static_cast<double>(std::abs(codec.sdf(v) - d)));
        max_w_err = std::max(max_w_err, static_cast<double>(std::abs(codec.weight(v) - w)));
        // Encoding a decoded value gives the same bits (no drift when a voxel is rewritten).
        CHECK(codec.encode(codec.sdf(v), codec.weight(v)) == v);
    }
    // Half a quantum, plus float rounding of the scaling (< 1 %).
    CHECK(max_sdf_err <= 0.5 * codec.sdfQuantum() * 1.01);
    CHECK(max_w_err <= 0.5 * codec.weightQuantum() * 1.01);
    // Signs and the exact ends of the ranges.
    CHECK(codec.sdf(codec.encode(-0.3f, 1.0f)) == Approx(-0.3f));
    CHECK(codec.sdf(codec.encode(0.3f, 1.0f)) == Approx(0.3f));
    CHECK(codec.weight(codec.encode(0.0f, 100.0f)) == Approx(100.0f));
    CHECK(codec.sdf(codec.encode(-1e-6f, 1.0f)) == 0.0f);
}

TEST_CASE("Packed voxels clamp out-of-range values and keep positive weights observed",
          "[tsdf][codec]") {
    const TsdfCodec codec(0.3f, 100.0f);
    CHECK(codec.sdf(codec.encode(5.0f, 1.0f)) == Approx(0.3f));
    CHECK(codec.sdf(codec.encode(-5.0f, 1.0f)) == Approx(-0.3f));
    CHECK(codec.weight(codec.encode(0.0f, 1e6f)) == Approx(100.0f));
    CHECK(codec.weight(codec.encode(0.0f, -1.0f)) == 0.0f);
    // A weight far below the quantum still encodes to one quantum, never to "unobserved".
    CHECK(codec.weight(codec.encode(0.0f, 1e-7f)) == Approx(codec.weightQuantum()));
    const std::uint32_t bg = codec.background();
    CHECK(codec.sdf(bg) == Approx(0.3f));
    CHECK(codec.weight(bg) == 0.0f);
    CHECK_THROWS_AS(TsdfCodec(0.0f, 1.0f), InvalidInput);
    CHECK_THROWS_AS(TsdfCodec(0.3f, -1.0f), InvalidInput);
    CHECK_THROWS_AS(TsdfCodec(std::nanf(""), 1.0f), InvalidInput);
}

TEST_CASE("The integrator refuses truncation or weight beyond the map's ranges", "[tsdf][codec]") {
    VoxelMap map(0.1, 0.3f, 100.0f);
    AtsdfConfig c = plainAtsdfConfig();
    c.truncation.max_m = 0.3;
    CHECK_NOTHROW(AtsdfIntegrator(map, c));
    c.truncation.max_m = 0.5;
    CHECK_THROWS_AS(AtsdfIntegrator(map, c), ConfigError);
    c.truncation.max_m = 0.3;
    c.max_weight = 1000.0;
    CHECK_THROWS_AS(AtsdfIntegrator(map, c), ConfigError);
    CHECK_THROWS_AS(VoxelMap(0.1, 0.0f), InvalidInput);
}

TEST_CASE("setVoxel and probeVoxel go through the codec", "[tsdf][codec]") {
    VoxelMap map(0.1, 0.3f, 100.0f);
    float d = 1.0f, w = 1.0f;
    CHECK_FALSE(map.probeVoxel(openvdb::Coord(1, 2, 3), d, w));
    CHECK(d == Approx(0.3f));  // the background: +sdf range, weight 0
    CHECK(w == 0.0f);
    map.setVoxel(openvdb::Coord(1, 2, 3), -0.125f, 2.5f);
    REQUIRE(map.probeVoxel(openvdb::Coord(1, 2, 3), d, w));
    CHECK(d == Approx(-0.125f).margin(map.codec().sdfQuantum()));
    CHECK(w == Approx(2.5f).margin(map.codec().weightQuantum()));
    CHECK(map.activeVoxelCount() == 1);
    CHECK(map.leafCount() == 1);
    const auto surface = map.surfaceGrid();
    CHECK(surface->getGridClass() == openvdb::GRID_LEVEL_SET);
    CHECK(surface->tree().getValue(openvdb::Coord(1, 2, 3)) == d);
    CHECK(surface->background() == Approx(0.3f));
    CHECK(map.weightGrid()->tree().getValue(openvdb::Coord(1, 2, 3)) == w);
}
