// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <set>

#include "unit/KittiFixture.h"
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/LabelSet.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

namespace {

std::shared_ptr<Dataset> openKitti(const std::filesystem::path& root) {
    DatasetConfig config;
    config.path = root.string();
    return Dataset::open(config);
}

}  // namespace

TEST_CASE("KITTI layout errors name the file and the problem", "[io][dataset]") {
    test::TempDir dir;
    const test::KittiFixture fixture(dir.path());
    REQUIRE(openKitti(dir.path())->numFrames() == 3);

    SECTION("fewer poses than scans") {
        writeKittiPoses(dir / "poses.txt", {fixture.T_W_C0[0], fixture.T_W_C0[1]});
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir.path()); }),
                   Contains("poses.txt") && Contains("has 2 poses") && Contains("3 scans"));
    }
    SECTION("missing poses file") {
        std::filesystem::remove(dir / "poses.txt");
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir.path()); }), Contains("poses.txt"));
    }
    SECTION("malformed calib.txt") {
        test::writeText(dir / "calib.txt",
                        "P2: 500 0 320 0 0 480 240 0 0 0 1\nTr: 1 0 0 0 0 1 0 "
                        "0 0 0 1 0\n");
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir.path()); }),
                   Contains("calib.txt:1") && Contains("P2"));
    }
    SECTION("calib without P2 for image_2") {
        KittiCalib calib = fixture.calib;
        calib.P[2].reset();
        writeKittiCalib(dir / "calib.txt", calib);
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir.path()); }),
                   Contains("calib.txt") && Contains("P2"));
    }
    SECTION("missing folders") {
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir / "nope"); }), Contains("nope"));
        std::filesystem::remove_all(dir / "velodyne");
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir.path()); }), Contains("velodyne"));
    }
    SECTION("requested camera folder missing") {
        DatasetConfig config;
        config.path = dir.path().string();
        config.cameras = {"image_3"};
        CHECK_THAT(test::ioErrorMessage([&] { Dataset::open(config); }), Contains("image_3"));
    }
    SECTION("unreadable image") {
        test::writeText(dir / "image_2" / "000000.png", "this is not a png");
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir.path()); }),
                   Contains("000000.png") && Contains("unreadable"));
    }
    SECTION("truncated scan is reported when loaded") {
        test::writeText(dir / "velodyne" / "000001.bin", std::string(40, '\0'));
        const auto dataset = openKitti(dir.path());
        CHECK_THAT(test::ioErrorMessage([&] { dataset->loadScan(1); }),
                   Contains("000001.bin") && Contains("40"));
    }
    SECTION("hidden files named like scans are not frames") {
        // Another process's temporary file (AtomicFile's name) and macOS's AppleDouble file.
        test::writeText(dir / "velodyne" / ".000001.bin.tmp123-0.bin", std::string(32, '\0'));
        test::writeText(dir / "velodyne" / "._000002.bin", "Mac OS X resource fork");
        const auto dataset = openKitti(dir.path());
        CHECK(dataset->numFrames() == 3);
        CHECK_NOTHROW(dataset->loadScan(2));
    }
    SECTION("times.txt shorter than the sequence") {
        test::writeText(dir / "times.txt", "0.0\n");
        CHECK_THAT(test::ioErrorMessage([&] { openKitti(dir.path()); }), Contains("times.txt"));
    }
}

TEST_CASE("Bad dataset options throw ConfigError naming the option", "[io][dataset]") {
    test::TempDir dir;
    const test::KittiFixture fixture(dir.path());
    DatasetConfig config;
    config.path = dir.path().string();
    config.first_frame = 3;
    CHECK_THROWS_WITH(Dataset::open(config), Contains("first_frame") && Contains("3"));
    config.first_frame = 0;
    config.format = "rosbag";
    CHECK_THROWS_AS(Dataset::open(config), ConfigError);
    config.format = "kitti";
    config.cameras = {"left"};
    CHECK_THROWS_WITH(Dataset::open(config), Contains("left"));
}

TEST_CASE("Generic layout: PCD scans, TUM poses, one camera from a K/D/T file", "[io][dataset]") {
    test::TempDir dir;
    std::vector<StampedPose> poses;
    for (int i = 0; i < 2; ++i) {
        PointCloud scan;
        scan.points = {{4, 0, 0}, {0, 3, 1}};
        writePcd(dir / "clouds" / ("scan_" + std::to_string(i) + ".pcd"), scan,
                 PcdEncoding::BinaryCompressed);
        StampedPose pose;
        pose.timestamp_s = 100.0 + i;
        pose.T_W_S.translation() = Vec3d(i, 2.0 * i, 0);
        poses.push_back(pose);
    }
    writeTumPoses(dir / "traj.tum", poses);
    writePng(dir / "cam" / "scan_1.png", cv::Mat(30, 40, CV_8UC3, cv::Scalar(0, 0, 0)));
    test::writeText(dir / "cam.txt",
                    "K: 100 0 20 0 100 15 0 0 1\nD: 0.1 0 0 0\n"
                    "T: 0 -1 0 0 0 0 -1 0 1 0 0 0.5\n");

    DatasetConfig config;
    config.format = "generic";
    config.path = dir.path().string();
    config.scans_dir = "clouds";
    config.poses_file = "traj.tum";
    config.pose_format = "tum";
    config.image_dir = "cam";
    config.calib_file = "cam.txt";
    const auto dataset = Dataset::open(config);
    REQUIRE(dataset->numFrames() == 2);
    CHECK(dataset->frame(1).id == "scan_1");
    CHECK(dataset->frame(1).timestamp_s == 101.0);
    CHECK(dataset->frame(1).T_W_L.translation() == Vec3d(1, 2, 0));
    REQUIRE(dataset->cameras().size() == 1);
    const Camera& camera = dataset->cameras()[0];
    CHECK(camera.intrinsics.width == 40);
    CHECK(camera.intrinsics.height == 30);
    CHECK(camera.intrinsics.hasDistortion());
    CHECK(dataset->missingImages() == 1);
    // Generic poses are the sensor's: T_W_C = T_W_L * T_C_L^-1, the camera looks along x_L.
    const Vec3d X_W = dataset->frame(1).T_W_L * Vec3d(5, 0, 0);
    CHECK((dataset->T_W_C(1, 0).inverse() * X_W).isApprox(Vec3d(0, 0, 5.5), 1e-12));
    CHECK(dataset->loadScan(0).size() == 2);

    SECTION("inline intrinsics and a 4x4 T_C_L") {
        config.calib_file.clear();
        config.intrinsics = {100, 100, 20, 15};
        config.T_C_L = {0, -1, 0, 0, 0, 0, -1, 0, 1, 0, 0, 0.5, 0, 0, 0, 1};
        const auto inline_calib = Dataset::open(config);
        CHECK(inline_calib->T_W_C(1, 0).isApprox(dataset->T_W_C(1, 0), 1e-12));
        CHECK_FALSE(inline_calib->cameras()[0].intrinsics.hasDistortion());
        config.T_C_L.resize(7);
        CHECK_THROWS_WITH(Dataset::open(config), Contains("T_C_L"));
    }
    SECTION("fewer TUM poses than scans") {
        writeTumPoses(dir / "traj.tum", {poses[0]});
        CHECK_THAT(test::ioErrorMessage([&] { Dataset::open(config); }),
                   Contains("traj.tum") && Contains("1 poses") && Contains("2 scans"));
    }
}

TEST_CASE("DatasetConfig declares every option with a doc", "[io][dataset]") {
    DatasetConfig config;
    OptionSpec spec;
    config.declareOptions(spec);
    std::set<std::string> keys;
    for (const OptionInfo& info : spec.options()) {
        CHECK_FALSE(info.doc.empty());
        keys.insert(info.key);
    }
    for (const char* key :
         {"format", "path", "drive", "min_range_m", "max_range_m", "first_frame", "num_frames",
          "stride", "cameras", "scans_dir", "poses_file", "pose_format", "image_dir",
          "semantic_dir", "intrinsics", "distortion", "T_C_L", "calib_file", "labels_file"}) {
        CHECK(keys.count(key) == 1);
    }
    CHECK(spec.find("min_range_m")->unit == "m");
    spec.set("min_range_m", OptionValue(2.5));
    CHECK(config.min_range_m == 2.5);
    spec.set("cameras", OptionValue(std::vector<std::string>{"image_3"}));
    CHECK(config.cameras == std::vector<std::string>{"image_3"});
}

TEST_CASE("Dataset labels: default or labels_file relative to the YAML folder", "[io][dataset]") {
    test::TempDir dir;
    const test::KittiFixture fixture(dir.path());
    test::writeText(dir / "labels.txt", "0, ground, 1 2 3\n7, thing, 4 5 6\n");
    DatasetConfig config;
    config.path = ".";
    CHECK(Dataset::open(config, dir.path())->labels().size() == 21);
    config.labels_file = "labels.txt";
    const LabelSet labels = Dataset::open(config, dir.path())->labels();
    CHECK(labels.size() == 2);
    CHECK(labels.name(7) == "thing");
}

TEST_CASE("Generic layout on the real LiDAR + camera frame", "[io][dataset]") {
    const auto frame = std::filesystem::path(VDBMAP_TEST_DATA_DIR) / "lidar_camera_real" / "1";
    test::TempDir dir;
    std::filesystem::create_directories(dir / "scans");
    std::filesystem::create_directories(dir / "images");
    std::filesystem::copy_file(frame / "calib.pcd", dir / "scans" / "000000.pcd");
    std::filesystem::copy_file(frame / "calib.jpg", dir / "images" / "000000.jpg");
    writeKittiPoses(dir / "poses.txt", {Isometry3d::Identity()});
    DatasetConfig config;
    config.format = "generic";
    config.path = dir.path().string();
    config.image_dir = "images";
    config.calib_file = (frame / "calib.txt").string();  // absolute paths are kept
    const auto dataset = Dataset::open(config);
    REQUIRE(dataset->numFrames() == 1);
    REQUIRE(dataset->cameras().size() == 1);
    CHECK(dataset->cameras()[0].intrinsics.width == 1920);
    CHECK(dataset->cameras()[0].intrinsics.height == 1200);
    CHECK(dataset->missingImages() == 0);
    ScanReadStats stats;
    const PointCloud scan = dataset->loadScan(0, &stats);
    CHECK(stats.points_read == 101340);
    CHECK(scan.size() + stats.dropped_non_finite + stats.dropped_range == 101340);
    CHECK(scan.size() > 90000);
    for (const Vec3f& p : scan.points) {
        REQUIRE(p.allFinite());
        REQUIRE(p.norm() >= 1.0f);
    }
}
