// SPDX-License-Identifier: Apache-2.0
// The generic layout with a rig of cameras (`dataset: cameras:` as a list of maps): loading,
// per-camera poses against the closed form, missing images per camera, and the errors.
#include <catch2/catch.hpp>
#include <functional>
#include <nlohmann/json.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/io/PoseIO.h"
#include "vdbmap/pipeline/DatasetSection.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/render/Visibility.h"

using namespace vdbmap;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

/// Two frames of scans and LiDAR poses; camera "front" looks along +x_L, camera "left" along
/// +y_L (both level, image y down = -z_L). front has images for both frames, left only for
/// frame 0. Frame 1's LiDAR pose is yawed by 90 deg and moved to (1, 2, 0).
struct RigFixture {
    fs::path root;
    Isometry3d T_W_L1 = Isometry3d::Identity();

    explicit RigFixture(const fs::path& dir) : root(dir) {
        for (int i = 0; i < 2; ++i) {
            PointCloud scan;
            scan.points = {{4, 0, 0}, {0, 3, 1}};
            writeBin(root / "scans" / ("00000" + std::to_string(i) + ".bin"), scan);
        }
        T_W_L1.linear() = Eigen::AngleAxisd(M_PI / 2, Vec3d::UnitZ()).toRotationMatrix();
        T_W_L1.translation() = Vec3d(1, 2, 0);
        writeKittiPoses(root / "poses.txt", {Isometry3d::Identity(), T_W_L1});
        const cv::Mat image(30, 40, CV_8UC3, cv::Scalar(1, 2, 3));
        writePng(root / "img_f" / "000000.png", image);
        writePng(root / "img_f" / "000001.png", image);
        writePng(root / "sem_f" / "000000.png", cv::Mat(30, 40, CV_8UC1, cv::Scalar(2)));
        writePng(root / "img_l" / "000000.png", cv::Mat(60, 80, CV_8UC3, cv::Scalar(4, 5, 6)));
        // left looks along +y_L: z_C = y_L, image right x_C = x_L (the front), y_C = -z_L;
        // optical centre at (0, 0.25, 0) in L.
        CameraCalib left;
        left.intrinsics.fx = 50;
        left.intrinsics.fy = 50;
        left.intrinsics.cx = 39.5;
        left.intrinsics.cy = 29.5;
        Eigen::Matrix3d R_C_L;
        R_C_L << 1, 0, 0, 0, 0, -1, 0, 1, 0;
        left.T_C_L.linear() = R_C_L;
        left.T_C_L.translation() = -R_C_L * Vec3d(0, 0.25, 0);
        writeCameraCalib(root / "calib_left.txt", left);
    }

    /// The YAML of a dataset section with both cameras: front inline, left by calib file.
    std::string yaml(const std::string& extra_front = "") const {
        return "dataset:\n"
               "  format: generic\n"
               "  path: " +
               root.string() +
               "\n"
               "  cameras:\n"
               "    - name: front\n"
               "      image_dir: img_f\n"
               "      semantic_dir: sem_f\n"
               "      intrinsics: [20, 20, 19.5, 14.5]\n"
               // x_C = -y_L, y_C = -z_L, z_C = x_L; optical centre at (0.5, 0, 0) in L.
               "      T_C_L: [0, -1, 0, 0,  0, 0, -1, 0,  1, 0, 0, -0.5]\n" +
               extra_front +
               "    - name: left\n"
               "      image_dir: img_l\n"
               "      calib_file: calib_left.txt\n";
    }
};

/// The pixel of world point X_W in camera `cam` at frame `i`, through the dataset's poses.
Vec2d pixelOf(const Dataset& dataset, std::size_t i, std::size_t cam, const Vec3d& X_W,
              double* depth = nullptr) {
    const Vec3d X_C = dataset.T_W_C(i, cam).inverse() * X_W;
    Vec2d pixel;
    REQUIRE(dataset.cameras()[cam].intrinsics.project(X_C, pixel));
    if (depth != nullptr) *depth = X_C.z();
    return pixel;
}

std::string configErrorMessage(const std::function<void()>& f) {
    try {
        f();
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "<no ConfigError thrown>";
}

}  // namespace

TEST_CASE("Generic layout: a two-camera rig loads with the right pose per camera",
          "[io][dataset][rig]") {
    test::TempDir dir;
    const RigFixture fixture(dir.path());
    test::writeText(dir / "dataset.yaml", fixture.yaml());
    const DatasetSection section = loadDatasetSection(dir / "dataset.yaml");
    REQUIRE(section.config.rig.size() == 2);
    CHECK(section.config.rig[1].calib_file == "calib_left.txt");
    const auto dataset = Dataset::open(section.config, section.base_dir);
    REQUIRE(dataset->numFrames() == 2);
    REQUIRE(dataset->cameras().size() == 2);
    const Camera& front = dataset->cameras()[0];
    const Camera& left = dataset->cameras()[1];
    CHECK(front.name == "front");
    CHECK(left.name == "left");
    CHECK(front.intrinsics.width == 40);
    CHECK(front.intrinsics.height == 30);
    CHECK(left.intrinsics.width == 80);  // each camera's size from its own images
    CHECK(left.intrinsics.height == 60);
    CHECK(left.intrinsics.fx == 50.0);

    // Frame 0 (T_W_L = I). A point 10 m ahead, 1 m to the right (-y_L) and 2 m up: the front
    // camera (centre x_L = 0.5) sees it at depth 9.5, u = cx + 20 * 1 / 9.5, v = cy - 20 * 2 / 9.5.
    double depth = 0;
    Vec2d px = pixelOf(*dataset, 0, 0, Vec3d(10, -1, 2), &depth);
    CHECK(depth == Approx(9.5));
    CHECK(px.x() == Approx(19.5 + 20.0 / 9.5));
    CHECK(px.y() == Approx(14.5 - 40.0 / 9.5));
    // The left camera (centre y_L = 0.25): a point 8.25 m to the left, 1 m ahead, 0.5 m down
    // is at depth 8, u = cx + 50 * 1 / 8, v = cy + 50 * 0.5 / 8.
    px = pixelOf(*dataset, 0, 1, Vec3d(1, 8.25, -0.5), &depth);
    CHECK(depth == Approx(8.0));
    CHECK(px.x() == Approx(39.5 + 50.0 / 8));
    CHECK(px.y() == Approx(29.5 + 25.0 / 8));

    // Frame 1: the LiDAR is yawed by 90 deg at (1, 2, 0), so "ahead" is +y_W and "left" -x_W.
    px = pixelOf(*dataset, 1, 0, Vec3d(1 + 1, 2 + 10, 2), &depth);  // 1 m right = +x_W
    CHECK(depth == Approx(9.5));
    CHECK(px.x() == Approx(19.5 + 20.0 / 9.5));
    CHECK(px.y() == Approx(14.5 - 40.0 / 9.5));
    px = pixelOf(*dataset, 1, 1, Vec3d(1 - 8.25, 2 + 1, -0.5), &depth);
    CHECK(depth == Approx(8.0));
    CHECK(px.x() == Approx(39.5 + 50.0 / 8));
    CHECK(px.y() == Approx(29.5 + 25.0 / 8));
    // The optical centres in the world.
    CHECK(dataset->T_W_C(1, 0).translation().isApprox(Vec3d(1, 2.5, 0), 1e-12));
    CHECK(dataset->T_W_C(1, 1).translation().isApprox(Vec3d(0.75, 2, 0), 1e-12));

    // The left camera lacks the image of frame 1: reported per camera, and that view is skipped.
    CHECK(dataset->missingImages() == 1);
    CHECK(dataset->missingImages(0) == 0);
    CHECK(dataset->missingImages(1) == 1);
    CHECK_THROWS_AS(dataset->missingImages(2), std::out_of_range);
    CHECK_FALSE(dataset->imagePath(1, 1).has_value());
    CHECK(dataset->semanticPath(0, 0).has_value());
    CHECK_FALSE(dataset->semanticPath(0, 1).has_value());  // left has no semantic folder
    CHECK(dataset->missingSemantics() == 1);               // front, frame 1
    const std::vector<View> views = datasetViews(*dataset, true, false);
    REQUIRE(views.size() == 3);
    CHECK((views[2].frame == 1 && views[2].camera == 0));
    CHECK(views[1].intrinsics.width == 80);
    CHECK(datasetViews(*dataset, false, true).size() == 1);
}

TEST_CASE("Generic rig: the C++ API and the single-camera keys give the same cameras",
          "[io][dataset][rig]") {
    test::TempDir dir;
    const RigFixture fixture(dir.path());
    DatasetConfig config;
    config.format = "generic";
    config.path = dir.path().string();
    DatasetCameraConfig front;
    front.image_dir = "img_f";
    front.intrinsics = {20, 20, 19.5, 14.5};
    front.T_C_L = {0, -1, 0, 0, 0, 0, -1, 0, 1, 0, 0, -0.5};
    config.rig = {front};
    const auto rig = Dataset::open(config);
    REQUIRE(rig->cameras().size() == 1);
    CHECK(rig->cameras()[0].name == "img_f");  // no name: the folder's

    // Backwards compatible: the same camera from the top-level keys.
    DatasetConfig single;
    single.format = "generic";
    single.path = dir.path().string();
    single.image_dir = "img_f";
    single.intrinsics = front.intrinsics;
    single.T_C_L = front.T_C_L;
    const auto one = Dataset::open(single);
    REQUIRE(one->cameras().size() == 1);
    CHECK(one->T_W_C(1, 0).isApprox(rig->T_W_C(1, 0), 1e-15));
    CHECK(one->cameras()[0].name == "img_f");
}

TEST_CASE("Generic rig: bad camera entries give clear errors", "[io][dataset][rig][yaml]") {
    test::TempDir dir;
    const RigFixture fixture(dir.path());
    const fs::path yaml = dir / "dataset.yaml";
    auto load = [&](const std::string& text) {
        test::writeText(yaml, text);
        const DatasetSection section = loadDatasetSection(yaml);
        Dataset::open(section.config, section.base_dir);
    };

    SECTION("unknown key: file:line:col, the entry and the valid keys") {
        const std::string msg = configErrorMessage([&] { load(fixture.yaml("      fx: 20\n")); });
        CHECK_THAT(msg, Contains(yaml.string() + ":10:7") && Contains("dataset: cameras[0]") &&
                            Contains("unknown key 'fx'") &&
                            Contains("valid keys: name, image_dir, semantic_dir, intrinsics, "
                                     "distortion, T_C_L, calib_file"));
    }
    SECTION("wrong type") {
        const std::string msg =
            configErrorMessage([&] { load(fixture.yaml("      distortion: none\n")); });
        CHECK_THAT(msg, Contains(":10:7") && Contains("cameras[0]") &&
                            Contains("key 'distortion'") && Contains("expected list<double>") &&
                            Contains("string 'none'"));
    }
    SECTION("a camera map without image_dir") {
        const std::string msg = configErrorMessage(
            [&] { load("dataset:\n  format: generic\n  path: .\n  cameras:\n    - name: a\n"); });
        CHECK_THAT(msg, Contains(":5:7") && Contains("cameras[0]") &&
                            Contains("missing required key 'image_dir'"));
    }
    SECTION("a list mixing folder names and maps") {
        const std::string msg = configErrorMessage([&] {
            load(
                "dataset:\n  format: generic\n  path: .\n  cameras:\n    - img_f\n"
                "    - {image_dir: img_l, calib_file: calib_left.txt}\n");
        });
        CHECK_THAT(msg, Contains(":4:3") && Contains("mixing both"));
    }
    SECTION("camera maps with the KITTI layout, folder names with the generic layout") {
        std::string text = fixture.yaml();
        text.replace(text.find("generic"), 7, "kitti");
        CHECK_THAT(configErrorMessage([&] { load(text); }),
                   Contains("KITTI layout") && Contains("camera map"));
        CHECK_THAT(configErrorMessage([&] {
                       load("dataset:\n  format: generic\n  path: .\n  cameras: [img_f]\n");
                   }),
                   Contains("generic layout") && Contains("'img_f'"));
    }
    SECTION("cameras together with the single-camera keys") {
        CHECK_THAT(configErrorMessage([&] { load(fixture.yaml() + "  image_dir: img_f\n"); }),
                   Contains("either the list 'cameras' or the single-camera keys"));
    }
    SECTION("calib_file together with inline intrinsics") {
        CHECK_THAT(
            configErrorMessage([&] { load(fixture.yaml() + "      intrinsics: [1, 1, 0, 0]\n"); }),
            Contains("dataset: cameras[1]") && Contains("'calib_file'") && Contains("not both"));
    }
    SECTION("missing T_C_L and bad intrinsics name the entry") {
        std::string text = fixture.yaml();
        text.erase(text.find("      T_C_L"),
                   text.find("    - name: left") - text.find("      T_C_L"));
        CHECK_THAT(configErrorMessage([&] { load(text); }),
                   Contains("dataset: cameras[0]") && Contains("'T_C_L'") && Contains("required"));
        std::string bad = fixture.yaml();
        bad.replace(bad.find("[20, 20, 19.5, 14.5]"), 20, "[20, 20, 19.5]");
        CHECK_THAT(configErrorMessage([&] { load(bad); }), Contains("dataset: cameras[0]") &&
                                                               Contains("'intrinsics'") &&
                                                               Contains("got 3 values"));
    }
    SECTION("two cameras with the same name") {
        std::string text = fixture.yaml();
        text.replace(text.find("name: left"), 10, "name: front");
        CHECK_THAT(configErrorMessage([&] { load(text); }),
                   Contains("dataset: cameras[1]") && Contains("'front' is used twice"));
    }
    SECTION("a missing image folder names the entry and the folder") {
        std::string text = fixture.yaml();
        text.replace(text.find("image_dir: img_l"), 16, "image_dir: img_x");
        CHECK_THAT(test::ioErrorMessage([&] { load(text); }),
                   Contains("dataset: cameras[1]") && Contains("img_x"));
    }
    SECTION("a bad calib file names the file and line") {
        test::writeText(dir / "calib_left.txt", "K: 50 0 39.5 0 50 29.5 0 0\nT: 1 0 0 0\n");
        CHECK_THAT(test::ioErrorMessage([&] { load(fixture.yaml()); }),
                   Contains("calib_left.txt:1"));
    }
}

TEST_CASE("Generic rig in a pipeline: report config, --set overrides, dataset-only files",
          "[io][dataset][rig][yaml]") {
    test::TempDir dir;
    const RigFixture fixture(dir.path());
    const std::string stages = "stages:\n  - stage: integrate.atsdf\n";
    auto pipeline = Pipeline::fromString(fixture.yaml() + stages, "rig.yaml", dir.path());
    REQUIRE(pipeline->datasetConfig().rig.size() == 2);
    const auto json = nlohmann::json::parse(pipeline->resolvedConfigJson());
    const auto& cameras = json["dataset"]["cameras"];
    REQUIRE(cameras.size() == 2);
    CHECK(cameras[0]["name"] == "front");
    CHECK(cameras[0]["intrinsics"] == std::vector<double>{20, 20, 19.5, 14.5});
    CHECK(cameras[1]["calib_file"] == "calib_left.txt");
    CHECK(cameras[1]["semantic_dir"] == "");

    // A flow-style list from --set replaces the file's cameras; an error in it names the --set.
    auto one =
        Pipeline::fromString(fixture.yaml() + stages, "rig.yaml", dir.path(),
                             {"dataset.cameras=[{image_dir: img_l, calib_file: calib_left.txt}]"});
    REQUIRE(one->datasetConfig().rig.size() == 1);
    CHECK(one->datasetConfig().rig[0].image_dir == "img_l");
    CHECK_THAT(configErrorMessage([&] {
                   Pipeline::fromString(fixture.yaml() + stages, "rig.yaml", dir.path(),
                                        {"dataset.cameras=[{image_dir: img_l, focal: 3}]"});
               }),
               Contains("--set dataset.cameras=") && Contains("cameras[0]") &&
                   Contains("unknown key 'focal'"));

    // loadDatasetSection reads only the dataset of a pipeline file, with overrides.
    test::writeText(dir / "pipeline.yaml", fixture.yaml() + stages);
    const DatasetSection section =
        loadDatasetSection(dir / "pipeline.yaml", {"dataset.num_frames=1"});
    CHECK(section.config.num_frames == 1);
    CHECK(section.config.rig.size() == 2);
    CHECK(Dataset::open(section.config, section.base_dir)->numFrames() == 1);
    CHECK_THAT(configErrorMessage([&] {
                   loadDatasetSection(dir / "pipeline.yaml", {"integrate.atsdf.voxel_size_m=1"});
               }),
               Contains("expected dataset.<key>=value"));
    test::writeText(dir / "none.yaml", stages);
    CHECK_THAT(configErrorMessage([&] { loadDatasetSection(dir / "none.yaml"); }),
               Contains("no 'dataset:' section"));
    test::writeText(dir / "typo.yaml", "datset:\n  path: .\n");
    CHECK_THAT(configErrorMessage([&] { loadDatasetSection(dir / "typo.yaml"); }),
               Contains("typo.yaml:1:1") && Contains("unknown top-level key 'datset'"));
}
