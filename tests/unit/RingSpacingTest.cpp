// SPDX-License-Identifier: Apache-2.0
// RingSpacing: the rings of a spinning LiDAR estimated from one scan, and the stretch of a
// grazing surface between two rings, against closed forms on a flat ground.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <random>

#include "support/SimLidar.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/map/RingSpacing.h"

using namespace vdbmap;
using namespace vdbmap::test;

namespace {

constexpr double kDeg = 3.141592653589793 / 180.0;
constexpr double kHeight = 1.73;  // sensor above the ground (KITTI)

SimLidarConfig hdl64Like() {
    SimLidarConfig lidar;  // 64 beams evenly over [-24.8, 2.0] deg
    lidar.azimuth_steps = 720;
    lidar.noise_sigma_m = 0.02;  // range noise moves points along their rays, not across rings
    return lidar;
}

double beamStepRad(const SimLidarConfig& l) {
    return (l.elevation_max_deg - l.elevation_min_deg) / (l.beams - 1) * kDeg;
}

std::vector<Vec3f> groundScan(const SimLidarConfig& lidar) {
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, -kHeight), Vec3d::UnitZ()});
    scene.add(SimBox{Vec3d(6, -2, -kHeight), Vec3d(8, 2, 1.0)});  // rings above the horizon
    return simulateScan(scene, lidar, poseAt(Vec3d::Zero()));
}

}  // namespace

TEST_CASE("RingSpacing finds the beams of a spinning LiDAR in one scan", "[tsdf][rings]") {
    const SimLidarConfig lidar = hdl64Like();
    const RingSpacing rings = RingSpacing::estimate(groundScan(lidar));
    REQUIRE(rings.valid());
    // Every beam hits the ground or the box (the box reaches 2.7 m above the sensor at 6 m:
    // the top beam, +2 deg, hits it).
    CHECK(rings.rings() == 64);
    const double step = beamStepRad(lidar);
    // Below the horizon: the gap up to the next beam; above it: down to the next one.
    for (const double elev_deg : {-24.8, -20.0, -10.0, -3.0}) {
        const double beam = std::round((elev_deg - lidar.elevation_min_deg) / (step / kDeg));
        const double elev = (lidar.elevation_min_deg * kDeg) + beam * step;
        INFO("elevation " << elev / kDeg << " deg");
        CHECK(rings.gapTowardsHorizon(static_cast<float>(std::sin(elev))) ==
              Approx(step).epsilon(0.02));
    }
    // The beam nearest to the horizon below it reaches only the horizon (-0.127 deg here).
    const double last_below = lidar.elevation_min_deg * kDeg + 58 * step;
    CHECK(last_below < 0.0);
    CHECK(rings.gapTowardsHorizon(static_cast<float>(std::sin(last_below))) ==
          Approx(-last_below).epsilon(0.1));
}

TEST_CASE("RingSpacing's surface gap on a flat ground is the distance to the next ring",
          "[tsdf][rings]") {
    const SimLidarConfig lidar = hdl64Like();
    const RingSpacing rings = RingSpacing::estimate(groundScan(lidar));
    REQUIRE(rings.valid());
    const double step = beamStepRad(lidar);
    const Vec3d up = Vec3d::UnitZ(), n = Vec3d::UnitZ();
    for (int beam = 10; beam <= 50; beam += 10) {
        // Closed form: beam b hits the ground at x_b = h / tan(-theta_b), the next beam up at
        // x_{b+1}; the gap is x_{b+1} - x_b.
        const double theta = lidar.elevation_min_deg * kDeg + beam * step;
        const double x = kHeight / std::tan(-theta);
        const double x_next = kHeight / std::tan(-(theta + step));
        const Vec3d p(x * std::cos(0.3), x * std::sin(0.3), -kHeight);  // any azimuth
        const Vec3d dir = p.normalized();
        const double gap = rings.surfaceGap(dir, n, up, p.norm());
        INFO("beam " << beam << " at " << x << " m: gap " << gap << " m, exact " << x_next - x);
        CHECK(gap == Approx(x_next - x).epsilon(0.005));
        // The normal's sign does not matter.
        CHECK(rings.surfaceGap(dir, Vec3d(-n), up, p.norm()) == Approx(gap));
    }
}

TEST_CASE("RingSpacing's surface gap vanishes where the rings do not run across the surface",
          "[tsdf][rings]") {
    const RingSpacing rings = RingSpacing::estimate(groundScan(hdl64Like()));
    REQUIRE(rings.valid());
    const Vec3d up = Vec3d::UnitZ();
    // A wall along the ray's azimuth, grazed sideways: a ring step moves the point up the wall,
    // not along the ray.
    const Vec3d p(10.0, 3.0, 0.0);
    const Vec3d dir = (p + Vec3d(0, 0, -0.05)).normalized();
    CHECK(rings.surfaceGap(dir, Vec3d::UnitY().eval(), up, p.norm()) < 0.02);
    // A surface facing the ray: n_perp = 0, the ring step does not move along it.
    const Vec3d frontal = Vec3d(1, 0, -0.2).normalized();
    CHECK(rings.surfaceGap(frontal, Vec3d(-frontal), up, 10.0) == 0.0);
    // Beyond the last ring that meets the ground, the next one misses it: an infinite gap.
    // (Beam 58 at -0.127 deg; its gap reaches the horizon, more than the 0.1 deg to the ground.)
    const double theta = -0.1 * kDeg;
    const Vec3d far_dir(std::cos(theta), 0.0, std::sin(theta));
    CHECK(std::isinf(rings.surfaceGap(far_dir, Vec3d::UnitZ().eval(), up, 990.0)));
}

TEST_CASE("RingSpacing is not valid for a scan without rings", "[tsdf][rings]") {
    // Points spread evenly over the sphere (e.g. a solid-state or a merged cloud).
    std::mt19937 rng(7);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<Vec3f> points(60000);
    for (Vec3f& p : points) p = Vec3f(g(rng), g(rng), g(rng)).normalized() * 10.0f;
    const RingSpacing rings = RingSpacing::estimate(points);
    CHECK_FALSE(rings.valid());
    CHECK(rings.gapTowardsHorizon(-0.1f) == 0.0f);
    CHECK(rings.surfaceGap(Vec3d(1, 0, -0.1).normalized().eval(), Vec3d::UnitZ().eval(),
                           Vec3d::UnitZ().eval(), 10.0) == 0.0);
    CHECK_FALSE(RingSpacing::estimate({}).valid());
}

TEST_CASE("RingSpacing from known elevations", "[tsdf][rings]") {
    // Uneven rings, as a VLS-128's: dense near the horizon.
    const RingSpacing rings =
        RingSpacing::fromElevations({-25 * kDeg, -10 * kDeg, -2 * kDeg, -1.89 * kDeg, 0.1 * kDeg, 3 * kDeg});
    REQUIRE(rings.valid());
    CHECK(rings.rings() == 6);
    CHECK(rings.gapTowardsHorizon(static_cast<float>(std::sin(-25 * kDeg))) == Approx(15 * kDeg).epsilon(1e-3));
    CHECK(rings.gapTowardsHorizon(static_cast<float>(std::sin(-2 * kDeg))) == Approx(0.11 * kDeg).epsilon(0.05));
    // Below the horizon, the last ring's gap ends at the horizon.
    CHECK(rings.gapTowardsHorizon(static_cast<float>(std::sin(-1.89 * kDeg))) == Approx(1.89 * kDeg).epsilon(1e-3));
    // Above it, towards the horizon means down.
    CHECK(rings.gapTowardsHorizon(static_cast<float>(std::sin(3 * kDeg))) == Approx(2.9 * kDeg).epsilon(1e-3));
    CHECK(rings.gapTowardsHorizon(static_cast<float>(std::sin(0.1 * kDeg))) == Approx(0.1 * kDeg).epsilon(0.05));
}

TEST_CASE("RingSpacing is not valid for a real HDL-64 scan, whose lasers sit off the origin",
          "[tsdf][rings][real]") {
    // KITTI's HDL-64E: each laser is offset from the sensor's origin (up to ~0.2 m), so its
    // elevation seen from the origin changes with the range and the rings smear into one band.
    // The estimate must say so rather than invent rings (the band behind grazing points then
    // stays as without the option).
    const auto path = std::filesystem::path(VDBMAP_TEST_DATA_DIR) / "kitti_scans_real" / "000000.bin";
    const std::vector<Vec3f> scan = readBin(path).points;
    REQUIRE(scan.size() == 124668);
    CHECK_FALSE(RingSpacing::estimate(scan).valid());
    // The same sensor simulated with its beams leaving the origin has its 64 rings.
    CHECK(RingSpacing::estimate(groundScan(hdl64Like())).rings() == 64);
}
