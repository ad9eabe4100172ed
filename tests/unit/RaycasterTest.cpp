// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"

using vdbmap::Raycaster;
using vdbmap::Vec3f;

namespace {

// Square [-1,1]^2 in the plane z = 0, normal +z.
Raycaster squarePlane() {
    std::vector<Vec3f> v{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    std::vector<std::array<std::uint32_t, 3>> t{{0, 1, 2}, {0, 2, 3}};
    return Raycaster(v, t);
}

// UV sphere of radius r around the origin.
Raycaster uvSphere(float r, int n_lat, int n_lon) {
    std::vector<Vec3f> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    for (int i = 0; i <= n_lat; ++i) {
        const double th = M_PI * i / n_lat;
        for (int j = 0; j < n_lon; ++j) {
            const double ph = 2 * M_PI * j / n_lon;
            v.emplace_back(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph),
                           r * std::cos(th));
        }
    }
    auto idx = [&](int i, int j) { return static_cast<std::uint32_t>(i * n_lon + (j % n_lon)); };
    for (int i = 0; i < n_lat; ++i) {
        for (int j = 0; j < n_lon; ++j) {
            t.push_back({idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)});
            t.push_back({idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)});
        }
    }
    return Raycaster(v, t);
}

}  // namespace

TEST_CASE("Raycaster hits a plane at the analytic distance", "[raycaster]") {
    const Raycaster rc = squarePlane();
    REQUIRE(rc.numTriangles() == 2);
    const auto hit = rc.intersect(Vec3f(0.2f, 0.3f, 5.0f), Vec3f(0, 0, -1));
    REQUIRE(hit);
    CHECK(hit->distance == Approx(5.0f).epsilon(1e-6));
    CHECK(std::abs(hit->normal_unit.z()) == Approx(1.0f));
    // Slanted ray: distance = 5 / cos(angle).
    const Vec3f dir = Vec3f(0.1f, 0.0f, -1.0f).normalized();
    const auto hit2 = rc.intersect(Vec3f(0.0f, 0.0f, 5.0f), dir);
    REQUIRE(hit2);
    CHECK(hit2->distance == Approx(5.0f / std::abs(dir.z())).epsilon(1e-5));
    // Misses: outside the square, pointing away, beyond t_max.
    CHECK_FALSE(rc.intersect(Vec3f(2.0f, 0.0f, 5.0f), Vec3f(0, 0, -1)));
    CHECK_FALSE(rc.intersect(Vec3f(0.0f, 0.0f, 5.0f), Vec3f(0, 0, 1)));
    CHECK_FALSE(rc.intersect(Vec3f(0.0f, 0.0f, 5.0f), Vec3f(0, 0, -1), 0.0f, 4.0f));
    CHECK(rc.occluded(Vec3f(0.0f, 0.0f, 5.0f), Vec3f(0, 0, -1), 0.0f, 6.0f));
    CHECK_FALSE(rc.occluded(Vec3f(0.0f, 0.0f, 5.0f), Vec3f(0, 0, -1), 0.0f, 4.0f));
}

TEST_CASE("Raycaster closest point matches point-to-triangle geometry", "[raycaster]") {
    const Raycaster rc = squarePlane();
    const auto above = rc.closestPoint(Vec3f(0.2f, 0.3f, 2.0f));
    REQUIRE(above);
    CHECK(above->distance == Approx(2.0f));
    CHECK(above->point.isApprox(Vec3f(0.2f, 0.3f, 0.0f), 1e-5f));
    // Beyond a corner: distance to the corner (1,1,0).
    const auto corner = rc.closestPoint(Vec3f(2.0f, 2.0f, 0.0f));
    REQUIRE(corner);
    CHECK(corner->distance == Approx(std::sqrt(2.0f)));
    // Beyond an edge, above the plane.
    const auto edge = rc.closestPoint(Vec3f(0.0f, 3.0f, 4.0f));
    REQUIRE(edge);
    CHECK(edge->distance == Approx(std::sqrt(4.0f + 16.0f)));
    // Radius limit.
    CHECK_FALSE(rc.closestPoint(Vec3f(0.0f, 0.0f, 2.0f), 1.0f));
}

TEST_CASE("Raycaster on a sphere agrees with the closed form", "[raycaster]") {
    const float r = 2.0f;
    const Raycaster rc = uvSphere(r, 64, 128);
    std::mt19937 rng(7);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    std::vector<Vec3f> dirs;
    for (int i = 0; i < 2000; ++i) {
        dirs.push_back(Vec3f(gauss(rng), gauss(rng), gauss(rng)).normalized());
    }
    // Rays from the centre hit at ~r (chord error of the tessellation is < 1 %).
    std::vector<std::optional<Raycaster::Hit>> hits;
    rc.intersect({Vec3f::Zero()}, dirs, 100.0f, hits);
    REQUIRE(hits.size() == dirs.size());
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        REQUIRE(hits[i]);
        CHECK(hits[i]->distance == Approx(r).epsilon(0.01));
        // Batched equals single.
        const auto single = rc.intersect(Vec3f::Zero(), dirs[i]);
        REQUIRE(single);
        CHECK(single->face == hits[i]->face);
    }
    // Closest-point distance from outside points = |p| - r.
    for (int i = 0; i < 200; ++i) {
        const Vec3f p = dirs[i] * (r + 0.5f + 0.01f * i);
        const auto cp = rc.closestPoint(p);
        REQUIRE(cp);
        CHECK(cp->distance == Approx(p.norm() - r).margin(0.01));
    }
}

TEST_CASE("Raycaster rejects bad triangles", "[raycaster]") {
    std::vector<Vec3f> v{{0, 0, 0}, {1, 0, 0}};
    std::vector<std::array<std::uint32_t, 3>> t{{0, 1, 2}};
    CHECK_THROWS_AS(Raycaster(v, t), vdbmap::InvalidInput);
    const Raycaster empty({}, {});
    CHECK_FALSE(empty.intersect(Vec3f::Zero(), Vec3f(1, 0, 0)));
    CHECK_FALSE(empty.closestPoint(Vec3f::Zero()));
}
