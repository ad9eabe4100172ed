// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/eval/CameraCoverage.h"
#include "vdbmap/render/Raycaster.h"

using namespace vdbmap;

namespace {

// A 100 x 100 px camera 5 m above the origin looking straight down (x_C = x_W, y_C = -y_W,
// z_C = -z_W): the ground z = 0 is inside the image for |x|, |y| < 5 * 50 / 50 = 5 m.
View downView() {
    View v;
    v.intrinsics.width = 100;
    v.intrinsics.height = 100;
    v.intrinsics.fx = v.intrinsics.fy = 50.0;
    v.intrinsics.cx = v.intrinsics.cy = 49.5;
    Isometry3d T_W_C = Isometry3d::Identity();
    T_W_C.linear() = Vec3d(1, -1, -1).asDiagonal();
    T_W_C.translation() = Vec3d(0, 0, 5);
    v.T_C_W = T_W_C.inverse();
    return v;
}

// A 2 x 2 m roof at z = 2.5 above the origin: its shadow on the ground from the camera at
// z = 5 is the square |x|, |y| < 2 (similar triangles).
Raycaster roof() {
    const std::vector<Vec3f> v{{-1, -1, 2.5f}, {1, -1, 2.5f}, {1, 1, 2.5f}, {-1, 1, 2.5f}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 1, 2}, {0, 2, 3}};
    return Raycaster(v, t);
}

}  // namespace

TEST_CASE("Ground points are seen inside the image and outside the roof's shadow",
          "[eval][coverage]") {
    const Raycaster scene = roof();
    const std::vector<Vec3f> points{{0, 0, 0},   {1.9f, 0, 0}, {2.1f, 0, 0}, {4.9f, 4.9f, 0},
                                    {5.1f, 0, 0}, {0, -3, 0},  {0, 0, 6}};
    const std::vector<Vec3f> normals(points.size(), Vec3f::UnitZ());
    const auto seen = pointsSeenByViews(points, normals, {downView()}, scene);
    // Hidden by the roof, hidden, seen, seen (corner), outside the image, seen, behind.
    CHECK(seen == std::vector<std::uint8_t>{0, 0, 1, 1, 0, 1, 0});
    // Without views nothing is seen; a second view beside the roof sees under its edge.
    CHECK(pointsSeenByViews(points, normals, {}, scene) == std::vector<std::uint8_t>(7, 0));
    View side = downView();
    Isometry3d T_W_C = side.T_C_W.inverse();
    T_W_C.translation() = Vec3d(1.5, 0, 5);
    side.T_C_W = T_W_C.inverse();
    const auto both = pointsSeenByViews(points, normals, {downView(), side}, scene);
    CHECK(both[1] == 1);  // (1.9, 0): the ray from (1.5, 0, 5) meets z = 2.5 at x = 1.7
    CHECK(both[0] == 0);  // (0, 0): at x = 0.75, under the roof
}

TEST_CASE("Grazing surfaces, depth limits and bad input", "[eval][coverage]") {
    const Raycaster scene = roof();
    const std::vector<Vec3f> points{{3, 0, 0}, {3, 0, 0}, {3, 0, 0}};
    // The ray to the camera (-3, 0, 5) is 31 degrees from +z (either side counts) and 59
    // degrees from +x.
    const std::vector<Vec3f> normals{Vec3f::UnitZ(), -Vec3f::UnitZ(), Vec3f::UnitX()};
    CoverageOptions o;
    CHECK(pointsSeenByViews(points, normals, {downView()}, scene, o) ==
          std::vector<std::uint8_t>{1, 1, 1});
    o.max_view_angle_deg = 45.0;
    CHECK(pointsSeenByViews(points, normals, {downView()}, scene, o) ==
          std::vector<std::uint8_t>{1, 1, 0});
    o = CoverageOptions{};
    o.max_depth_m = 4.0;
    CHECK(pointsSeenByViews(points, normals, {downView()}, scene, o) ==
          std::vector<std::uint8_t>{0, 0, 0});
    CHECK_THROWS_AS(pointsSeenByViews(points, {Vec3f::UnitZ()}, {downView()}, scene),
                    InvalidInput);
    o = CoverageOptions{};
    o.max_view_angle_deg = 0.0;
    CHECK_THROWS_AS(pointsSeenByViews(points, normals, {downView()}, scene, o), InvalidInput);
    View bad = downView();
    bad.intrinsics.width = 0;
    CHECK_THROWS_AS(pointsSeenByViews(points, normals, {bad}, scene), InvalidInput);
}
