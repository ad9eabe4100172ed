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

TEST_CASE("Noise weight: the inverse variance of the distance along the normal", "[tsdf][weight]") {
    // var = sigma_0^2 (1 + q^2 c^2): frontal 1, edge-on 1 + q^2, in between the closed form.
    const double q = 3.0;
    CHECK(noiseWeight(1.0, q) == Approx(1.0));
    CHECK(noiseWeight(0.0, q) == Approx(10.0));
    CHECK(noiseWeight(0.5, q) == Approx(10.0 / 3.25));
    // Two samples of the same surface at c = 1 and c = 0.2 with range noise sigma_r = q sigma_0:
    // the weighted mean of their distances has the least variance with these weights.
    const double c1 = 1.0, c2 = 0.2, s0 = 1.0, sr = q * s0;
    const double v1 = s0 * s0 + c1 * c1 * sr * sr, v2 = s0 * s0 + c2 * c2 * sr * sr;
    auto var = [&](double w1, double w2) { return (w1 * w1 * v1 + w2 * w2 * v2) / ((w1 + w2) * (w1 + w2)); };
    const double best = var(noiseWeight(c1, q), noiseWeight(c2, q));
    CHECK(best == Approx(1.0 / (1.0 / v1 + 1.0 / v2)));
    CHECK(best < var(1.0, 1.0));
    CHECK(best < var(c1, c2));  // the paper's incidence weight
    CHECK(noiseWeight(0.3, 0.0) == 1.0);  // q = 0: uniform
}

TEST_CASE("Distance falloff along the ray", "[tsdf][weight]") {
    const double l = 0.1, inv_l2 = 1.0 / (l * l);
    CHECK(distanceFalloff(0.0, inv_l2, 0.1) == 1.0);
    CHECK(distanceFalloff(0.1, inv_l2, 0.1) == Approx(0.5));
    CHECK(distanceFalloff(-0.2, inv_l2, 0.1) == Approx(0.2));
    CHECK(distanceFalloff(0.5, inv_l2, 0.1) == Approx(0.1));  // 1/26 < floor
    CHECK(distanceFalloff(5.0, 0.0, 0.1) == 1.0);             // no falloff
}
