// SPDX-License-Identifier: Apache-2.0
// vdbmap-sim --rig surround: the rig's closed form, and a small sequence that loads back
// through its dataset.yaml with every camera projecting where the closed form says.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/io/PoseIO.h"
#include "vdbmap/pipeline/DatasetSection.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/sim/SimRig.h"
#include "vdbmap/sim/SimSequence.h"

using namespace vdbmap;
namespace fs = std::filesystem;

namespace {

// Yaw of each rig camera's optical axis in the vehicle frame, in surroundRig's order.
const std::pair<const char*, double> kYawDeg[] = {
    {"front", 0.0}, {"left", 90.0}, {"rear", 180.0}, {"right", -90.0}};

}  // namespace

TEST_CASE("The surround rig: four level cameras, square pixels, centred principal point",
          "[sim][rig]") {
    SurroundRigOptions o;
    o.width_px = 1280;
    o.height_px = 720;
    o.hfov_deg = 90.0;
    const std::vector<RigCamera> rig = surroundRig(o);
    REQUIRE(rig.size() == 4);
    for (std::size_t c = 0; c < 4; ++c) {
        INFO(rig[c].name);
        CHECK(rig[c].name == kYawDeg[c].first);
        const CameraIntrinsics& K = rig[c].intrinsics;
        CHECK(K.fx == Approx(640.0));  // 90 deg: (1280 / 2) / tan(45 deg)
        CHECK(K.fy == K.fx);
        CHECK(K.cx == 639.5);
        CHECK(K.cy == 359.5);
        CHECK_FALSE(K.hasDistortion());
        const double yaw = kYawDeg[c].second * M_PI / 180.0;
        const Vec3d axis(std::cos(yaw), std::sin(yaw), 0);
        CHECK(rig[c].T_V_C.rotation().col(2).isApprox(axis, 1e-12));             // z: the axis
        CHECK(rig[c].T_V_C.rotation().col(1).isApprox(Vec3d(0, 0, -1), 1e-12));  // y: down
        CHECK(rig[c].T_V_C.rotation().determinant() == Approx(1.0));
        CHECK(rig[c].T_V_C.translation().isApprox(0.25 * axis + Vec3d(0, 0, 1.6), 1e-12));
        // The image's left edge of one camera is the right edge of the next: 4 x 90 deg.
        Vec2d px;
        const Vec3d edge_V = rig[c].T_V_C.translation() +
                             10.0 * Vec3d(std::cos(yaw + M_PI / 4), std::sin(yaw + M_PI / 4), 0);
        REQUIRE(K.project(rig[c].T_V_C.inverse() * edge_V, px));
        CHECK(px.x() == Approx(639.5 - 640.0));
    }
    o.hfov_deg = 180.0;
    CHECK_THROWS_AS(surroundRig(o), InvalidInput);
}

TEST_CASE("A surround-rig street loads back through its dataset.yaml", "[sim][rig]") {
    test::TempDir dir;
    const fs::path seq = dir / "rig";
    SimOptions o;
    o.scene = "street";
    o.frames = 2;
    o.size_m = 20;
    o.seed = 3;
    o.gt_views = 0;
    o.quiet = true;
    o.rig = "surround";
    o.rig_options.width_px = 192;
    o.rig_options.height_px = 108;
    o.rig_options.hfov_deg = 100.0;
    REQUIRE(writeSimSequence(o, seq).frames == 2);
    for (const char* f : {"scans/000001.bin", "poses.txt", "dataset.yaml", "calib_front.txt",
                          "calib_rear.txt", "image_left/000000.png", "semantic_right/000001.png",
                          "vignetting.txt", "exposure.txt", "gt/mesh.ply", "gt/sim.json"}) {
        INFO(f);
        CHECK(fs::exists(seq / f));
    }
    CHECK_FALSE(fs::exists(seq / "calib.txt"));
    CHECK_FALSE(fs::exists(seq / "velodyne"));

    const DatasetSection section = loadDatasetSection(seq / "dataset.yaml");
    CHECK(section.config.format == "generic");
    const auto dataset = Dataset::open(section.config, section.base_dir);
    REQUIRE(dataset->numFrames() == 2);
    REQUIRE(dataset->cameras().size() == 4);
    CHECK(dataset->missingImages() == 0);
    CHECK(dataset->missingSemantics() == 0);
    const double f_px = 96.0 / std::tan(50.0 * M_PI / 180.0);
    // The street's LiDAR is 1.73 m above the vehicle origin, level: T_V_L = [I | (0, 0, 1.73)].
    Isometry3d T_V_L = Isometry3d::Identity();
    T_V_L.translation() = Vec3d(0, 0, 1.73);
    for (std::size_t c = 0; c < 4; ++c) {
        const Camera& camera = dataset->cameras()[c];
        INFO(camera.name);
        CHECK(camera.name == kYawDeg[c].first);
        CHECK(camera.intrinsics.width == 192);
        CHECK(camera.intrinsics.height == 108);
        CHECK(camera.intrinsics.fx == Approx(f_px));
        CHECK(camera.intrinsics.cy == 53.5);
        // The calib file says the same as dataset.yaml.
        const CameraCalib calib = readCameraCalib(seq / ("calib_" + camera.name + ".txt"));
        CHECK(calib.T_C_L.isApprox(camera.T_C_L, 1e-12));
        CHECK(calib.intrinsics.fx == camera.intrinsics.fx);
        // A point 10 m along the optical axis from the camera's mount, 1 m up and 2 m to the
        // image's right (V frame: right of yaw is (sin, -cos, 0)), through the dataset's poses:
        // depth 10, u = cx + f * 2 / 10, v = cy - f * 1 / 10.
        const double yaw = kYawDeg[c].second * M_PI / 180.0;
        const Vec3d axis(std::cos(yaw), std::sin(yaw), 0), right(std::sin(yaw), -std::cos(yaw), 0);
        const Vec3d X_V =
            0.25 * axis + Vec3d(0, 0, 1.6) + 10.0 * axis + Vec3d(0, 0, 1) + 2.0 * right;
        for (std::size_t i = 0; i < 2; ++i) {
            const Isometry3d T_W_V = dataset->frame(i).T_W_L * T_V_L.inverse();
            const Vec3d X_C = dataset->T_W_C(i, c).inverse() * (T_W_V * X_V);
            Vec2d px;
            REQUIRE(camera.intrinsics.project(X_C, px));
            CHECK(X_C.z() == Approx(10.0));
            CHECK(px.x() == Approx(95.5 + f_px * 0.2));
            CHECK(px.y() == Approx(53.5 - f_px * 0.1));
        }
    }

    // The poses are the LiDAR's own: scan points land on the ground truth.
    std::vector<std::uint8_t> labels;
    const TriMesh gt = readMeshPly(seq / "gt" / "mesh.ply", &labels);
    const Raycaster gt_rc = Raycaster::fromMesh(gt);
    const PointCloud scan = dataset->loadScan(1);
    REQUIRE(scan.size() > 20000);
    std::size_t near = 0, checked = 0;
    for (std::size_t i = 0; i < scan.size(); i += 50, ++checked) {
        const Vec3f p_W = (dataset->frame(1).T_W_L * scan.points[i].cast<double>()).cast<float>();
        const auto cp = gt_rc.closestPoint(p_W, 1.0f);
        if (cp && cp->distance < 0.1f) ++near;
    }
    CHECK(static_cast<double>(near) / checked > 0.99);

    // Each camera's semantic image shows the class of the ground-truth face through its pixels
    // (the rear camera at the end of the street, the others at its start, so that every one
    // looks along or across it).
    for (std::size_t c = 0; c < 4; ++c) {
        const Camera& camera = dataset->cameras()[c];
        INFO(camera.name);
        const std::size_t frame = camera.name == "rear" ? 1 : 0;
        const cv::Mat sem = readLabelImage(*dataset->semanticPath(frame, c));
        const Isometry3d T_W_C = dataset->T_W_C(frame, c);
        std::size_t agree = 0, total = 0, labelled = 0;
        for (int y = 2; y < sem.rows; y += 5) {
            for (int x = 2; x < sem.cols; x += 5) {
                const Vec3d d_C((x - camera.intrinsics.cx) / camera.intrinsics.fx,
                                (y - camera.intrinsics.cy) / camera.intrinsics.fy, 1.0);
                const Vec3f dir_W = (T_W_C.rotation() * d_C.normalized()).cast<float>();
                const auto hit = gt_rc.intersect(T_W_C.translation().cast<float>(), dir_W);
                const int expected = hit ? labels[hit->face] : 255;
                agree += sem.at<std::uint8_t>(y, x) == expected;
                labelled += expected != 255;
                ++total;
            }
        }
        CHECK(static_cast<double>(agree) / total > 0.97);
        CHECK(labelled > total / 4);  // every camera sees the street, not only the sky
    }

    // The KITTI rig of the same seed has the same scans and ground truth.
    o.rig = "kitti";
    o.images = false;
    writeSimSequence(o, dir / "kitti");
    CHECK(test::readBytes(dir / "kitti" / "gt" / "mesh.ply") ==
          test::readBytes(seq / "gt" / "mesh.ply"));
    CHECK(test::readBytes(dir / "kitti" / "velodyne" / "000001.bin") ==
          test::readBytes(seq / "scans" / "000001.bin"));
    // --cameras is for the kitti rig only.
    o.rig = "surround";
    o.cameras = 2;
    CHECK_THROWS_AS(writeSimSequence(o, dir / "bad"), ConfigError);
    o.cameras = 1;
    o.rig = "fisheye";
    CHECK_THROWS_AS(writeSimSequence(o, dir / "bad"), ConfigError);
}
