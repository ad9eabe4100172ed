// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/CalibIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

namespace {

// The first lines of a real KITTI odometry calib.txt (sequence 00).
const char* kKittiCalib =
    "P0: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n"
    "P1: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 -3.861448000000e+02 "
    "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n"
    "P2: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 4.538225000000e+01 "
    "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 -1.130887000000e-01 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 3.779761000000e-03\n"
    "P3: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 -3.372877000000e+02 "
    "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 2.369057000000e+00 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 4.915215000000e-03\n"
    "Tr: 4.276802385584e-04 -9.999672484946e-01 -8.084491683471e-03 -1.198459927713e-02 "
    "-7.210626507497e-03 8.081198471645e-03 -9.999413164504e-01 -5.403984729748e-02 "
    "9.999738645903e-01 4.859485810390e-04 -7.206933692422e-03 -2.921968648686e-01\n";

}  // namespace

TEST_CASE("KITTI calib: P0..P3 and Tr; camera k from P_k = K [I | t]", "[io][calib]") {
    test::TempDir dir;
    test::writeText(dir / "calib.txt", kKittiCalib);
    const KittiCalib calib = readKittiCalib(dir / "calib.txt");
    for (int k = 0; k < 4; ++k) REQUIRE(calib.P[k].has_value());
    CHECK(calib.Tr.matrix()(0, 1) == Approx(-9.999672484946e-01));
    CHECK(calib.Tr.translation().z() == Approx(-2.921968648686e-01));

    const Camera cam2 = kittiCamera(*calib.P[2], calib.Tr, "image_2", "semantic_2");
    CHECK(cam2.intrinsics.fx == Approx(718.856));
    CHECK(cam2.intrinsics.cy == Approx(185.2157));
    CHECK_FALSE(cam2.intrinsics.hasDistortion());
    // Oracle: P2 applied to X_C0 = Tr X_L must equal K * (T_C2_L X_L), for any X_L.
    for (const Vec3d& X_L : {Vec3d(10, 2, -1), Vec3d(35, -8, 0.5), Vec3d(6, 0.1, 1.2)}) {
        const Vec3d X_C0 = calib.Tr * X_L;
        const Vec3d uvw = *calib.P[2] * X_C0.homogeneous();
        Vec2d pixel;
        REQUIRE(cam2.intrinsics.project(cam2.T_C_L * X_L, pixel));
        CHECK(pixel.x() == Approx(uvw.x() / uvw.z()).epsilon(1e-10));
        CHECK(pixel.y() == Approx(uvw.y() / uvw.z()).epsilon(1e-10));
    }
    // Camera 2 sits ~6 cm beside camera 0 (KITTI): t_2 = K^-1 P2[:,3], solved by hand:
    // z = P2(2,3), y = (P2(1,3) - cy z) / fy, x = (P2(0,3) - cx z) / fx.
    const double tz = 3.779761e-03;
    const Vec3d t2((4.538225e+01 - 6.071928e+02 * tz) / 7.18856e+02,
                   (-1.130887e-01 - 1.852157e+02 * tz) / 7.18856e+02, tz);
    // KITTI's Tr rotation is orthonormal only to ~1e-7, so compare with that tolerance.
    const Isometry3d T_C2_C0(cam2.T_C_L.matrix() * calib.Tr.matrix().inverse());
    CHECK((T_C2_C0.translation() - t2).norm() < 1e-6);
    CHECK(T_C2_C0.linear().isIdentity(1e-9));

    // "Tr_velo_to_cam" is accepted; unknown keys ignored; write/read round trip.
    KittiCalib copy = calib;
    writeKittiCalib(dir / "out" / "calib.txt", copy);
    const KittiCalib back = readKittiCalib(dir / "out" / "calib.txt");
    CHECK(back.Tr.isApprox(calib.Tr, 1e-15));
    CHECK(back.P[3]->isApprox(*calib.P[3], 1e-15));
    test::writeText(dir / "velo.txt",
                    "R0_rect: 1 0 0 0 1 0 0 0 1\nTr_velo_to_cam: 0 -1 0 0.1 "
                    "0 0 -1 0.2 1 0 0 0.3\n");
    CHECK(readKittiCalib(dir / "velo.txt").Tr.translation() == Vec3d(0.1, 0.2, 0.3));
}

TEST_CASE("Malformed calib.txt throws IoError naming the file and line", "[io][calib]") {
    test::TempDir dir;
    test::writeText(dir / "count.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr: 1 0 0 0 1 0 0 0 1\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiCalib(dir / "count.txt"); }),
               Contains("count.txt:2") && Contains("12") && Contains("Tr"));
    test::writeText(dir / "number.txt", "Tr: 1 0 0 0 0 1 0 0 0 0 1 zero\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiCalib(dir / "number.txt"); }),
               Contains("number.txt:1"));
    test::writeText(dir / "colon.txt", "P0 1 0 0 0 0 1 0 0 0 0 1 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiCalib(dir / "colon.txt"); }),
               Contains("colon.txt:1"));
    test::writeText(dir / "notr.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiCalib(dir / "notr.txt"); }),
               Contains("notr.txt") && Contains("Tr"));
    CHECK_THAT(test::ioErrorMessage([&] { readKittiCalib(dir / "none.txt"); }),
               Contains("none.txt"));
}

TEST_CASE("Camera calib K / D / T file", "[io][calib]") {
    test::TempDir dir;
    test::writeText(dir / "calib.txt",
                    "K: 2152.8 0 971.3 0 2155.5 605.9 0 0 1\nD: -0.1192 0.162 0.00073985 0.0014\n"
                    "T: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n");
    const CameraCalib calib = readCameraCalib(dir / "calib.txt");
    CHECK(calib.intrinsics.fx == 2152.8);
    CHECK(calib.intrinsics.cy == 605.9);
    CHECK(calib.intrinsics.distortion[1] == 0.162);
    CHECK(calib.intrinsics.distortion[4] == 0.0);
    CHECK(calib.T_C_L * Vec3d(1, 0, 0) == Vec3d(0.1, 0.2, 1.3));
    test::writeText(dir / "bad.txt", "K: 1 0 0 0 1 0 0 0\nT: 1 0 0 0 0 1 0 0 0 0 1 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readCameraCalib(dir / "bad.txt"); }),
               Contains("bad.txt:1") && Contains("9"));
}

TEST_CASE("Projection: pinhole, radial symmetry and tangential terms", "[io][camera]") {
    CameraIntrinsics c;
    c.width = 640;
    c.height = 480;
    c.fx = 500;
    c.fy = 400;
    c.cx = 320;
    c.cy = 240;
    Vec2d pixel;
    CHECK_FALSE(c.project(Vec3d(1, 1, 0), pixel));
    CHECK_FALSE(c.project(Vec3d(1, 1, -2), pixel));
    REQUIRE(c.project(Vec3d(0.2, -0.1, 2.0), pixel));
    CHECK(pixel.isApprox(Vec2d(320 + 500 * 0.1, 240 - 400 * 0.05)));
    CHECK(c.inside(Vec2d(-0.5, -0.5)));
    CHECK_FALSE(c.inside(Vec2d(639.5, 10)));

    // Radial only: the normalised point moves along its ray by 1 + k1 r^2 + k2 r^4 + k3 r^6.
    c.distortion = {-0.2, 0.05, 0, 0, 0.01};
    REQUIRE(c.hasDistortion());
    const double x = 0.3, y = -0.4, r2 = x * x + y * y;
    const double scale = 1 - 0.2 * r2 + 0.05 * r2 * r2 + 0.01 * r2 * r2 * r2;
    REQUIRE(c.project(Vec3d(x, y, 1), pixel));
    CHECK(pixel.x() == Approx(320 + 500 * x * scale));
    CHECK(pixel.y() == Approx(240 + 400 * y * scale));

    // Tangential only, point on the x axis (y = 0): x' = x + 3 p2 x^2, y' = p1 x^2.
    c.distortion = {0, 0, 0.01, -0.02, 0};
    REQUIRE(c.project(Vec3d(0.5, 0, 1), pixel));
    CHECK(pixel.x() == Approx(320 + 500 * (0.5 - 0.02 * 3 * 0.25)));
    CHECK(pixel.y() == Approx(240 + 400 * 0.01 * 0.25));
}
