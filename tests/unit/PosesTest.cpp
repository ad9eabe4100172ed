// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/PoseIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

namespace {
Isometry3d pose(double angle_rad, const Vec3d& axis, const Vec3d& t) {
    Isometry3d T = Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
    T.translation() = t;
    return T;
}
}  // namespace

TEST_CASE("KITTI poses: 3x4 row-major lines, round trip", "[io][poses]") {
    test::TempDir dir;
    test::writeText(dir / "poses.txt",
                    "1 0 0 0 0 1 0 0 0 0 1 0\n\n"
                    "0 -1 0 1.5 1 0 0 -2 0 0 1 0.25\n");
    const std::vector<Isometry3d> poses = readKittiPoses(dir / "poses.txt");
    REQUIRE(poses.size() == 2);
    CHECK(poses[0].isApprox(Isometry3d::Identity()));
    CHECK((poses[1] * Vec3d(1, 0, 0)).isApprox(Vec3d(1.5, -1, 0.25)));

    const std::vector<Isometry3d> written = {pose(0.3, {1, 2, 3}, {4, -5, 6}),
                                             pose(-2.0, {0, 0, 1}, {0.1, 0.2, 0.3})};
    writeKittiPoses(dir / "out.txt", written);
    const std::vector<Isometry3d> back = readKittiPoses(dir / "out.txt");
    REQUIRE(back.size() == 2);
    CHECK(back[0].isApprox(written[0], 1e-15));
    CHECK(back[1].isApprox(written[1], 1e-15));
}

TEST_CASE("TUM poses: t tx ty tz qx qy qz qw, comments, round trip", "[io][poses]") {
    test::TempDir dir;
    // 90 degrees about z: q = (w, x, y, z) = (cos 45, 0, 0, sin 45).
    test::writeText(dir / "tum.txt",
                    "# timestamp tx ty tz qx qy qz qw\n"
                    "1305031102.175304 1 2 3 0 0 0.7071067811865476 0.7071067811865476\n"
                    "1305031102.275 0 0 0 0 0 0 2\n");
    const std::vector<StampedPose> poses = readTumPoses(dir / "tum.txt");
    REQUIRE(poses.size() == 2);
    CHECK(poses[0].timestamp_s == Approx(1305031102.175304));
    CHECK((poses[0].T_W_S * Vec3d(1, 0, 0)).isApprox(Vec3d(1, 3, 3)));
    CHECK(poses[1].T_W_S.linear().isIdentity(1e-12));  // normalised quaternion

    writeTumPoses(dir / "out.txt", poses);
    const std::vector<StampedPose> back = readTumPoses(dir / "out.txt");
    REQUIRE(back.size() == 2);
    CHECK(back[0].timestamp_s == poses[0].timestamp_s);
    CHECK(back[0].T_W_S.isApprox(poses[0].T_W_S, 1e-14));
}

TEST_CASE("Bad pose files throw IoError naming the file and line", "[io][poses]") {
    test::TempDir dir;
    test::writeText(dir / "short.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiPoses(dir / "short.txt"); }),
               Contains("short.txt:2") && Contains("12"));
    test::writeText(dir / "nan.txt", "1 0 0 nan 0 1 0 0 0 0 1 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiPoses(dir / "nan.txt"); }),
               Contains("nan.txt:1"));
    test::writeText(dir / "tum.txt", "# c\n0 1 2 3 0 0 0 1\n0 1 2 3 0 0 0 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readTumPoses(dir / "tum.txt"); }),
               Contains("tum.txt:3") && Contains("quaternion"));
    test::writeText(dir / "tum7.txt", "0 1 2 3 0 0 1\n");
    CHECK_THAT(test::ioErrorMessage([&] { readTumPoses(dir / "tum7.txt"); }),
               Contains("tum7.txt:1"));
    CHECK_THAT(test::ioErrorMessage([&] { readKittiPoses(dir / "missing.txt"); }),
               Contains("missing.txt"));
}
