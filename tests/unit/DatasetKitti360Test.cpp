// SPDX-License-Identifier: Apache-2.0
// format: kitti360 on a hand-written KITTI-360 root (Kitti360Fixture): frames with and without
// poses, the frame chain against the devkit's own route, and bad input.
#include <catch2/catch.hpp>
#include <sstream>

#include "unit/Kitti360Fixture.h"
#include "vdbmap/io/Dataset.h"

using namespace vdbmap;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

DatasetConfig kitti360Config(const fs::path& root) {
    DatasetConfig config;
    config.format = "kitti360";
    config.path = root.string();
    return config;
}

/// Replaces the line starting with `key` in a text file (removes it if `line` is empty).
void replaceLine(const fs::path& path, const std::string& key, const std::string& line) {
    std::istringstream in(test::readBytes(path));
    std::string text, current;
    while (std::getline(in, current)) {
        if (current.rfind(key, 0) == 0) {
            if (!line.empty()) text += line + "\n";
        } else {
            text += current + "\n";
        }
    }
    test::writeText(path, text);
}

}  // namespace

TEST_CASE("KITTI-360: frames without a pose are skipped and counted", "[io][dataset][kitti360]") {
    test::TempDir dir;
    const test::Kitti360Fixture fixture(dir.path());
    const auto dataset = Dataset::open(kitti360Config(dir.path()));
    CHECK(dataset->config().drive == test::Kitti360Fixture::kDrive);  // the only drive
    REQUIRE(dataset->numFrames() == 3);
    CHECK(dataset->framesWithoutPose() == 1);
    CHECK(dataset->frame(0).id == "0000000000");
    CHECK(dataset->frame(1).id == "0000000001");
    CHECK(dataset->frame(2).id == "0000000003");  // frame 2 has no pose
    CHECK(dataset->frame(2).timestamp_s == Approx(0.3).margin(1e-12));
    CHECK(dataset->posesPath() == dir / "data_poses" / test::Kitti360Fixture::kDrive / "poses.txt");
    REQUIRE(dataset->cameras().size() == 2);
    CHECK(dataset->cameras()[0].name == "image_00");
    CHECK(dataset->cameras()[1].name == "image_01");
    CHECK(dataset->cameras()[0].intrinsics.width == 96);
    CHECK(dataset->cameras()[0].intrinsics.fx == 552.55);
    CHECK(dataset->missingImages() == 2);  // frame 1 of both cameras
    CHECK(dataset->loadScan(2).size() == 2);

    SECTION("first_frame / stride apply to the posed frames") {
        DatasetConfig config = kitti360Config(dir.path());
        config.first_frame = 1;
        config.drive = test::Kitti360Fixture::kDrive;
        const auto later = Dataset::open(config);
        REQUIRE(later->numFrames() == 2);
        CHECK(later->frame(1).id == "0000000003");
    }
    SECTION("LiDAR only") {
        DatasetConfig config = kitti360Config(dir.path());
        config.cameras = {"image_00"};
        replaceLine(dir / "calibration" / "perspective.txt", "R_rect_01", "");
        CHECK(Dataset::open(config)->cameras().size() == 1);
        fs::remove_all(dir / "data_2d_raw");
        fs::remove(dir / "calibration" / "perspective.txt");
        CHECK(Dataset::open(kitti360Config(dir.path()))->cameras().empty());
    }
}

TEST_CASE("KITTI-360 frame chain: the Velodyne and the rectified cameras as the devkit places them",
          "[io][dataset][kitti360]") {
    test::TempDir dir;
    const test::Kitti360Fixture fixture(dir.path());
    const auto dataset = Dataset::open(kitti360Config(dir.path()));
    const Kitti360Calib& c = fixture.calib;
    const Isometry3d T_IMU_L = *c.T_IMU_C[0] * c.T_L_C0.inverse();  // the devkit's TrVeloToPose
    for (std::size_t i = 0; i < dataset->numFrames(); ++i) {
        const Isometry3d& T_W_IMU = fixture.poses[i].T_W_IMU;
        // A Velodyne point in the world: T_W_IMU * TrVeloToPose * X_L.
        const Vec3d X_L(12.0, -1.5, 0.7);
        const Vec3d X_W = T_W_IMU * T_IMU_L * X_L;
        CHECK((dataset->frame(i).T_W_L * X_L).isApprox(X_W, 1e-12));
        for (int k = 0; k < 2; ++k) {
            // The devkit's camera pose (project.py): cam2world = T_W_IMU * T_IMU_Ck * R_rect^-1,
            // pixel = K * X_Rk, K the left 3x3 of P_rect; no Velodyne on this route.
            Isometry3d R_rect = Isometry3d::Identity();
            R_rect.linear() = *c.R_rect[k];
            const Isometry3d cam2world = T_W_IMU * *c.T_IMU_C[k] * R_rect.inverse();
            const Vec3d X_R = cam2world.inverse() * X_W;
            const Vec3d uvw = c.P_rect[k]->leftCols<3>() * X_R;
            REQUIRE(uvw.z() > 0);
            // Ours: through the LiDAR pose and the camera's T_C_L.
            const Camera& camera = dataset->cameras()[k];
            Vec2d pixel;
            REQUIRE(camera.intrinsics.project(camera.T_C_L * X_L, pixel));
            CHECK(pixel.x() == Approx(uvw.x() / uvw.z()).margin(1e-8));
            CHECK(pixel.y() == Approx(uvw.y() / uvw.z()).margin(1e-8));
            CHECK(dataset->T_W_C(i, k).isApprox(cam2world, 1e-12));
        }
    }
    // Camera 0 is also P_rect_00 * [R_rect_00 * X_C0; 1] (P_rect_00's 4th column is zero).
    const Vec3d X_C0 = c.T_L_C0.inverse() * Vec3d(12.0, -1.5, 0.7);
    const Vec3d uvw = *c.P_rect[0] * (*c.R_rect[0] * X_C0).homogeneous();
    Vec2d pixel;
    REQUIRE(dataset->cameras()[0].intrinsics.project(
        dataset->cameras()[0].T_C_L * Vec3d(12.0, -1.5, 0.7), pixel));
    CHECK(pixel.isApprox(uvw.hnormalized(), 1e-10));
}

TEST_CASE("KITTI-360: bad input names the file and the line or key", "[io][dataset][kitti360]") {
    test::TempDir dir;
    const test::Kitti360Fixture fixture(dir.path());
    const fs::path calibration = dir / "calibration";
    const fs::path poses = dir / "data_poses" / test::Kitti360Fixture::kDrive / "poses.txt";
    const auto open = [&] { Dataset::open(kitti360Config(dir.path())); };

    SECTION("a calibration without the expected key names the key") {
        replaceLine(calibration / "perspective.txt", "R_rect_01", "");
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("perspective.txt") && Contains("'R_rect_01:'"));
        replaceLine(calibration / "calib_cam_to_pose.txt", "image_01", "");
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("calib_cam_to_pose.txt") && Contains("'image_01:'"));
    }
    SECTION("a malformed calibration line names file:line") {
        replaceLine(calibration / "perspective.txt", "R_rect_00", "R_rect_00: 2 0 0 0 1 0 0 0 1");
        CHECK_THAT(test::ioErrorMessage(open), Contains("perspective.txt:3") &&
                                                   Contains("R_rect_00") &&
                                                   Contains("not a rotation"));
        replaceLine(calibration / "perspective.txt", "R_rect_00", "R_rect_00: 1 0 0 0 1 0 0 0");
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("perspective.txt:3") && Contains("needs 9 numbers, got 8"));
        test::writeText(calibration / "calib_cam_to_velo.txt", "1 0 0 0 0 1 0 0 0 0 1\n");
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("calib_cam_to_velo.txt") && Contains("got 11"));
    }
    SECTION("a missing calibration file names it") {
        fs::remove(calibration / "calib_cam_to_pose.txt");
        CHECK_THAT(test::ioErrorMessage(open), Contains("calib_cam_to_pose.txt"));
    }
    SECTION("bad pose lines name file:line") {
        test::writeText(poses, test::readBytes(poses) + "7 1 0 0\n");
        CHECK_THAT(test::ioErrorMessage(open), Contains("poses.txt:4") && Contains("13 numbers"));
        writeKitti360Poses(poses, {fixture.poses[1], fixture.poses[0]});
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("poses.txt:2") && Contains("frames must increase"));
        test::writeText(poses, "0.5 1 0 0 0 0 1 0 0 0 0 1 0\n");
        CHECK_THAT(test::ioErrorMessage(open), Contains("poses.txt:1") && Contains("integer"));
    }
    SECTION("missing poses, missing scans, no scan with a pose") {
        fs::remove(poses);
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("KITTI-360 poses not found") && Contains("poses.txt"));
        writeKitti360Poses(poses, {{17, Isometry3d::Identity()}});
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("none of the 4 scans") && Contains("poses.txt"));
        fs::remove_all(dir / "data_3d_raw" / test::Kitti360Fixture::kDrive / "velodyne_points");
        CHECK_THAT(test::ioErrorMessage(open), Contains("velodyne_points"));
    }
    SECTION("a malformed timestamp names file:line") {
        const fs::path stamps = dir / "data_3d_raw" / test::Kitti360Fixture::kDrive /
                                "velodyne_points" / "timestamps.txt";
        replaceLine(stamps, "2013-05-28 08:46:00.550000000", "2013-05-28 08:46:0x.55");
        CHECK_THAT(test::ioErrorMessage(open),
                   Contains("timestamps.txt:4") && Contains("YYYY-MM-DD"));
    }
    SECTION("options: the drive, the cameras") {
        fs::create_directories(dir / "data_3d_raw" / "2013_05_28_drive_0009_sync");
        CHECK_THROWS_WITH(open(), Contains("drive") && Contains("2013_05_28_drive_0003_sync, "
                                                                "2013_05_28_drive_0009_sync"));
        DatasetConfig config = kitti360Config(dir.path());
        config.drive = "2013_05_28_drive_0042_sync";
        CHECK_THAT(test::ioErrorMessage([&] { Dataset::open(config); }),
                   Contains("2013_05_28_drive_0042_sync"));
        config.drive = test::Kitti360Fixture::kDrive;
        config.cameras = {"image_02"};
        CHECK_THROWS_AS(Dataset::open(config), ConfigError);
        CHECK_THROWS_WITH(Dataset::open(config), Contains("image_02"));
        config.format = "kitti";
        config.cameras.clear();
        CHECK_THROWS_WITH(Dataset::open(config), Contains("'drive' is for format 'kitti360'"));
    }
}
