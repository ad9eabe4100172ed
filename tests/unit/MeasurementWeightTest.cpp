// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <cmath>

#include "vdbmap/map/MeasurementWeight.h"

using namespace vdbmap;

TEST_CASE("Incidence weight is the cosine of the incidence angle with a floor", "[tsdf][weight]") {
    const Vec3d n = Vec3d::UnitZ();
    const Vec3d p(0, 0, 0);
    CHECK(incidenceWeight(n, Vec3d(0, 0, 5), p, 0.1) == Approx(1.0));
    // 60 degrees incidence: cos = 0.5.
    const Vec3d s60(5 * std::sin(M_PI / 3), 0, 5 * std::cos(M_PI / 3));
    CHECK(incidenceWeight(n, s60, p, 0.1) == Approx(0.5));
    // Grazing (89.9 deg) and from behind: the floor.
    const Vec3d graze(10, 0, 10 * std::tan(0.1 * M_PI / 180));
    CHECK(incidenceWeight(n, graze, p, 0.1) == Approx(0.1));
    CHECK(incidenceWeight(n, Vec3d(0, 0, -3), p, 0.1) == Approx(0.1));
    // Degenerate block (no normal): full weight.
    CHECK(incidenceWeight(Vec3d::Zero(), s60, p, 0.1) == Approx(1.0));
}

TEST_CASE("Weight drops off linearly behind the surface", "[tsdf][weight]") {
    const double eps = 0.3, vs = 0.1;
    CHECK(behindSurfaceFactor(0.2, eps, vs) == 1.0);
    CHECK(behindSurfaceFactor(-0.1, eps, vs) == 1.0);
    CHECK(behindSurfaceFactor(-0.2, eps, vs) == Approx(0.5));
    CHECK(behindSurfaceFactor(-0.3, eps, vs) == Approx(0.0).margin(1e-12));
    CHECK(behindSurfaceFactor(-0.5, 0.05, vs) == 1.0);  // eps <= voxel: no drop-off
}
