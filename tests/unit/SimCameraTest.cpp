// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <filesystem>

#include "sim/SimImaging.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/io/PoseIO.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/TexturedRender.h"
#include "vdbmap/sim/SimSequence.h"

using namespace vdbmap;
namespace fs = std::filesystem;

TEST_CASE("Vignetting follows the paper's g(r)", "[sim][camera]") {
    const std::array<double, 3> abc{0.3, 0.1, 0.05};
    CHECK(vignettingGain(abc, 100, 50, 100, 50) == Approx(1.0));
    // Corner (0, 0) of a centre (cx, cy) image: r = 1, g = 1 + a + b + c.
    CHECK(vignettingGain(abc, 0, 0, 100, 50) == Approx(1.45));
    // r^2 = 0.5 at half the corner distance squared.
    const double u = 100 + 100 / std::sqrt(2.0), v = 50 + 50 / std::sqrt(2.0);
    CHECK(vignettingGain(abc, u, v, 100, 50) ==
          Approx(1 + 0.3 * 0.5 + 0.1 * 0.25 + 0.05 * 0.125));
    cv::Mat img(101, 201, CV_8UC3, cv::Scalar(200, 200, 200));
    ImagingOptions o;
    o.vignetting_abc = abc;
    applyVignettingAndExposure(img, o, 0.9);
    CHECK(img.at<cv::Vec3b>(50, 100)[0] == 180);                       // centre: 200 * 0.9
    CHECK(img.at<cv::Vec3b>(0, 0)[1] == std::lround(200 * 0.9 / 1.45));  // corner
}

TEST_CASE("A textured plane renders its texture and labels", "[sim][camera]") {
    // Plane z = 5 in front of a camera looking along +z, texture constant BGR (10, 20, 30).
    ObjMesh mesh;
    mesh.positions = {{-50, -50, 5}, {50, -50, 5}, {50, 50, 5}, {-50, 50, 5}};
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh.materials.push_back(ObjMaterial{});
    mesh.triangles = {{{0, 1, 2}, {0, 1, 2}, 0}, {{0, 2, 3}, {0, 2, 3}, 0}};
    const std::vector<cv::Mat> tex{cv::Mat(4, 4, CV_8UC3, cv::Scalar(10, 20, 30))};
    const std::vector<std::uint8_t> labels{7, 7};
    const Raycaster rc(mesh.positions, {{0, 1, 2}, {0, 2, 3}});
    CameraIntrinsics K;
    K.width = 64;
    K.height = 48;
    K.fx = K.fy = 50;
    K.cx = 31.5;
    K.cy = 23.5;
    const RenderedView r = renderView({RenderLayer{&mesh, &tex, &rc, &labels}}, K,
                                      Isometry3d::Identity());
    for (int y = 0; y < K.height; y += 7) {
        for (int x = 0; x < K.width; x += 7) {
            CHECK(r.color.at<cv::Vec3b>(y, x) == cv::Vec3b(10, 20, 30));
            CHECK(r.labels.at<std::uint8_t>(y, x) == 7);
            // Ray distance to the plane z = 5 through pixel (x, y).
            const double dx = (x - K.cx) / K.fx, dy = (y - K.cy) / K.fy;
            CHECK(r.depth.at<float>(y, x) ==
                  Approx(5.0 * std::sqrt(1 + dx * dx + dy * dy)).epsilon(1e-5));
        }
    }
    // Looking away: nothing.
    Isometry3d back = Isometry3d::Identity();
    back.linear() = Eigen::AngleAxisd(M_PI, Vec3d::UnitY()).toRotationMatrix();
    const RenderedView none = renderView({RenderLayer{&mesh, &tex, &rc, &labels}}, K, back);
    CHECK(cv::countNonZero(none.labels != 255) == 0);
}

TEST_CASE("A simulated street sequence is consistent with its ground truth", "[sim][camera]") {
    const fs::path dir = fs::temp_directory_path() / "vdbmap_simcamera_test";
    fs::remove_all(dir);
    SimOptions o;
    o.scene = "street";
    o.frames = 3;
    o.size_m = 24;
    o.seed = 5;
    o.gt_views = 1;
    o.quiet = true;
    o.label_noise_px = 0;
    const SimSummary s = writeSimSequence(o, dir);
    REQUIRE(s.frames == 3);
    for (const char* f : {"calib.txt", "poses.txt", "times.txt", "velodyne/000002.bin",
                          "image_2/000000.png", "semantic_2/000002.png", "vignetting.txt",
                          "exposure.txt", "gt/mesh.ply", "gt/textured/mesh.obj",
                          "gt/observed_points.ply", "gt/views/views.json"}) {
        INFO(f);
        CHECK(fs::exists(dir / f));
    }
    const KittiCalib calib = readKittiCalib(dir / "calib.txt");
    CHECK_FALSE(calib.Tr.isApprox(Isometry3d::Identity()));
    const auto poses = readKittiPoses(dir / "poses.txt");
    REQUIRE(poses.size() == 3);
    CHECK(poses[0].isApprox(Isometry3d::Identity(), 1e-9));  // world = camera 0 at frame 0
    std::vector<std::uint8_t> labels;
    const TriMesh gt = readMeshPly(dir / "gt" / "mesh.ply", &labels);
    REQUIRE(labels.size() == gt.n_faces());
    const Raycaster gt_rc = Raycaster::fromMesh(gt);
    // LiDAR points through T_W_C0 * Tr land on the ground-truth surface (noise 2 cm).
    const PointCloud scan = readBin(dir / "velodyne" / "000002.bin");
    REQUIRE(scan.size() > 50000);
    const Isometry3d T_W_L = poses[2] * calib.Tr;
    std::size_t near = 0, checked = 0;
    for (std::size_t i = 0; i < scan.size(); i += 50, ++checked) {
        const Vec3f p_W = (T_W_L * scan.points[i].cast<double>()).cast<float>();
        const auto cp = gt_rc.closestPoint(p_W, 1.0f);
        if (cp && cp->distance < 0.1f) ++near;
    }
    CHECK(static_cast<double>(near) / checked > 0.99);
    // The semantic image agrees with the class of the face seen through each pixel.
    const cv::Mat sem = readLabelImage(dir / "semantic_2" / "000001.png");
    const Camera cam2 = kittiCamera(*calib.P[2], calib.Tr, "image_2");
    const Isometry3d T_W_C2 = poses[1] * (cam2.T_C_L * calib.Tr.inverse()).inverse();
    std::size_t agree = 0, total = 0;
    for (int y = 5; y < sem.rows; y += 37) {
        for (int x = 5; x < sem.cols; x += 41) {
            const Vec3d d_C((x - cam2.intrinsics.cx) / cam2.intrinsics.fx,
                            (y - cam2.intrinsics.cy) / cam2.intrinsics.fy, 1.0);
            const Vec3f dir_W = (T_W_C2.rotation() * d_C.normalized()).cast<float>();
            const auto hit = gt_rc.intersect(T_W_C2.translation().cast<float>(), dir_W);
            const int expected = hit ? labels[hit->face] : 255;
            agree += sem.at<std::uint8_t>(y, x) == expected;
            ++total;
        }
    }
    CHECK(static_cast<double>(agree) / total > 0.97);
    fs::remove_all(dir);
}
