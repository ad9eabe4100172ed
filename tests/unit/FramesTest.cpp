// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/KittiFixture.h"
#include "vdbmap/io/Dataset.h"

using namespace vdbmap;

TEST_CASE("KITTI frames: T_W_L = T_W_C0 * Tr and camera 2 through P2", "[io][frames]") {
    test::TempDir dir;
    const test::KittiFixture fixture(dir.path());
    DatasetConfig config;
    config.path = dir.path().string();
    const auto dataset = Dataset::open(config);
    REQUIRE(dataset->numFrames() == 3);
    REQUIRE(dataset->cameras().size() == 1);  // image_3 does not exist
    const Camera& camera = dataset->cameras()[0];
    CHECK(camera.name == "image_2");
    CHECK(camera.semantic_name == "semantic_2");
    CHECK(camera.intrinsics.width == 640);
    CHECK(camera.intrinsics.height == 480);

    // Frame 0: W is camera 0, so a point known in the LiDAR frame is Tr * X_L in the world.
    const Vec3d X_L0(10.0, 1.0, 0.5);
    const Vec3d X_W = fixture.calib.Tr * X_L0;
    CHECK((dataset->frame(0).T_W_L.inverse() * X_W).isApprox(X_L0, 1e-12));
    // With Tr ignored (the classic bug) the point would land elsewhere.
    CHECK_FALSE((fixture.T_W_C0[0].inverse() * X_W).isApprox(X_L0, 1e-3));

    for (std::size_t i = 0; i < 3; ++i) {
        // LiDAR frame: X_C0 = T_W_C0^-1 X_W, and X_L = Tr^-1 X_C0 (docs/DATA.md: X_C0 = Tr X_L).
        const Vec3d X_C0 = fixture.T_W_C0[i].inverse() * X_W;
        const Vec3d X_L = fixture.calib.Tr.inverse() * X_C0;
        CHECK((dataset->frame(i).T_W_L.inverse() * X_W).isApprox(X_L, 1e-12));
        CHECK((dataset->frame(i).T_W_L * X_L).isApprox(X_W, 1e-12));

        // Image: P2 applied to camera-0 coordinates vs. Dataset::T_W_C + intrinsics.project.
        const Vec3d uvw = *fixture.calib.P[2] * X_C0.homogeneous();
        const Vec2d expected(uvw.x() / uvw.z(), uvw.y() / uvw.z());
        Vec2d pixel;
        REQUIRE(camera.intrinsics.project(dataset->T_W_C(i, 0).inverse() * X_W, pixel));
        CHECK(pixel.x() == Approx(expected.x()).epsilon(1e-10));
        CHECK(pixel.y() == Approx(expected.y()).epsilon(1e-10));
        CHECK(camera.intrinsics.inside(pixel));
    }
    // Camera 2 centre in the world: camera 0's centre shifted by -t2 (P2 = K [I | t2]).
    const Vec3d centre_C0 = dataset->frame(1).T_W_L * camera.T_C_L.inverse() * Vec3d::Zero();
    CHECK(centre_C0.isApprox(fixture.T_W_C0[1] * Vec3d(-fixture.t2), 1e-12));
    CHECK(dataset->frame(2).timestamp_s == Approx(0.2));
}

TEST_CASE("Missing images are not errors but are counted", "[io][frames]") {
    test::TempDir dir;
    const test::KittiFixture fixture(dir.path());
    DatasetConfig config;
    config.path = dir.path().filename().string();
    const auto dataset = Dataset::open(config, dir.path().parent_path());
    CHECK(dataset->imagePath(0, 0).has_value());
    CHECK_FALSE(dataset->imagePath(1, 0).has_value());
    CHECK(dataset->imagePath(2, 0).has_value());
    CHECK(dataset->semanticPath(0, 0).has_value());
    CHECK_FALSE(dataset->semanticPath(2, 0).has_value());
    CHECK(dataset->missingImages() == 1);
    CHECK(dataset->missingSemantics() == 2);
}

TEST_CASE("Frame selection and scan filtering", "[io][frames]") {
    test::TempDir dir;
    const test::KittiFixture fixture(dir.path());
    DatasetConfig config;
    config.path = dir.path().string();
    config.first_frame = 1;
    config.stride = 1;
    config.num_frames = 1;
    const auto dataset = Dataset::open(config);
    REQUIRE(dataset->numFrames() == 1);
    CHECK(dataset->frame(0).id == "000001");
    CHECK(dataset->frame(0).index == 0);
    CHECK(dataset->frame(0).T_W_L.isApprox(fixture.T_W_C0[1] * fixture.calib.Tr, 1e-12));
    // Frame 1 has no image_2 file: the only camera has no image among the selected frames.
    CHECK(dataset->cameras().empty());

    ScanReadStats stats;
    const PointCloud scan = dataset->loadScan(0, &stats);
    CHECK(scan.size() == 2);
    CHECK(stats.points_read == 4);
    CHECK(stats.dropped_non_finite == 1);
    CHECK(stats.dropped_range == 1);  // the 0.36 m point is below min_range_m = 1

    config.first_frame = 0;
    config.stride = 2;
    config.num_frames = -1;
    const auto strided = Dataset::open(config);
    REQUIRE(strided->numFrames() == 2);
    CHECK(strided->frame(1).id == "000002");
    CHECK(strided->missingImages() == 0);
}
