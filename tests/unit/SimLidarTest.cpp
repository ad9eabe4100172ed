// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/sim/LidarModel.h"

using namespace vdbmap;

namespace {

// Ground plane z = 0, 400 m x 400 m.
Raycaster groundPlane() {
    std::vector<Vec3f> v{{-200, -200, 0}, {200, -200, 0}, {200, 200, 0}, {-200, 200, 0}};
    return Raycaster(v, {{0, 1, 2}, {0, 2, 3}});
}

Isometry3d lidarAt(double height) {
    Isometry3d T = Isometry3d::Identity();
    T.translation() = Vec3d(0, 0, height);
    return T;
}

}  // namespace

TEST_CASE("LiDAR presets carry the datasheet beam tables", "[sim][lidar]") {
    const LidarModel hdl = hdl64ePreset();
    REQUIRE(hdl.numBeams() == 64);
    CHECK(*std::max_element(hdl.elevations_deg.begin(), hdl.elevations_deg.end()) ==
          Approx(2.0));
    CHECK(*std::min_element(hdl.elevations_deg.begin(), hdl.elevations_deg.end()) ==
          Approx(-24.33).margin(0.01));
    CHECK(hdl.numAzimuths() == 2000);
    const LidarModel vls = vls128Preset();
    REQUIRE(vls.numBeams() == 128);
    CHECK(*std::max_element(vls.elevations_deg.begin(), vls.elevations_deg.end()) ==
          Approx(15.0));
    CHECK(*std::min_element(vls.elevations_deg.begin(), vls.elevations_deg.end()) ==
          Approx(-25.0));
    CHECK(lidarPreset("vls128").numBeams() == 128);
    CHECK_THROWS_AS(lidarPreset("hdl32"), ConfigError);
    for (const auto& d : hdl.rayDirections()) REQUIRE(d.norm() == Approx(1.0f));
}

TEST_CASE("Noise-free scan of a ground plane lands on the plane", "[sim][lidar]") {
    LidarModel m = hdl64ePreset();
    m.range_noise_sigma_m = 0.0;
    m.dropout_probability = 0.0;
    const Raycaster plane = groundPlane();
    const double h = 1.73;
    const LidarScan scan = simulateScan(m, plane, lidarAt(h), 1);
    // Every downward beam hits (range h / sin(-el) < 120 m for el <= -0.83 deg); the upward
    // ones and the horizon miss.
    std::size_t down = 0;
    for (double el : m.elevations_deg) {
        if (h / std::sin(-el * M_PI / 180.0) < m.max_range_m && el < 0) ++down;
    }
    CHECK(scan.points_L.size() == down * m.numAzimuths());
    for (std::size_t i = 0; i < scan.points_L.size(); i += 97) {
        const Vec3f& p = scan.points_L.points[i];
        CHECK(p.z() + h == Approx(0.0).margin(1e-4));
        CHECK(scan.true_points_W[i].z() == Approx(0.0).margin(1e-4));
    }
}

TEST_CASE("Range noise and dropout follow their parameters, deterministically",
          "[sim][lidar]") {
    LidarModel m = vls128Preset();
    m.range_noise_sigma_m = 0.05;
    m.dropout_probability = 0.2;
    const Raycaster plane = groundPlane();
    const LidarScan a = simulateScan(m, plane, lidarAt(2.3), 42);
    const LidarScan b = simulateScan(m, plane, lidarAt(2.3), 42);
    REQUIRE(a.points_L.size() == b.points_L.size());
    CHECK(a.points_L.points == b.points_L.points);
    m.dropout_probability = 0.0;
    m.range_noise_sigma_m = 0.0;
    const LidarScan full = simulateScan(m, plane, lidarAt(2.3), 42);
    const double kept = static_cast<double>(a.points_L.size()) / full.points_L.size();
    CHECK(kept == Approx(0.8).margin(0.01));
    // Range error = measured range - true range; its standard deviation is sigma.
    double sum = 0, sum2 = 0;
    const Vec3f origin(0, 0, 2.3f);
    for (std::size_t i = 0; i < a.points_L.size(); ++i) {
        const double e = a.points_L.points[i].norm() - (a.true_points_W[i] - origin).norm();
        sum += e;
        sum2 += e * e;
    }
    const double n = static_cast<double>(a.points_L.size());
    CHECK(sum / n == Approx(0.0).margin(0.002));
    CHECK(std::sqrt(sum2 / n) == Approx(0.05).epsilon(0.03));
}
