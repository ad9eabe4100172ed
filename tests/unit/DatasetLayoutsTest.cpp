// SPDX-License-Identifier: Apache-2.0
// The public datasets as they are downloaded (docs/DATA.md), written by `vdbmap-sim --layout`
// and read back: the KITTI-360 frame chain checked against what the simulator drew, the three
// layouts agreeing on the same simulated drive, and `vdbmap run` on each example config.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/CliRun.h"
#include "unit/IoTestUtil.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/sim/SimLayout.h"

using namespace vdbmap;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

constexpr const char* kDrive = "2013_05_28_drive_0000_sync";

fs::path workDir() {
    static const fs::path dir = test::freshProcessDir("vdbmap_layouts");
    static const test::RemoveAtExit cleanup{dir};
    return dir;
}

/// The simulated street (4 frames, 20 m, seed 3, two cameras) in `layout`, written by the
/// built vdbmap-sim as a user would. SemanticKITTI's labels carry SemanticKITTI's ids; the
/// KITTI-360 fixture's (in gt/labels) carry ours, to compare with the semantic images.
/// Written once for all test processes of a build (test_scratch/layouts, keyed by the build
/// times of the simulator and the library, so that a rebuilt writer writes anew): into a
/// folder of this process, then renamed into place, so that no process reads one being
/// written. Tests that break a fixture break a copy.
fs::path simulate(const std::string& layout) {
    const fs::path bin(VDBMAP_BINARY_DIR);
    const auto built = std::max(fs::last_write_time(test::kSimExe),
                                fs::last_write_time(bin / "lib" / "libvdbmap.so"));
    const std::string key = std::to_string(built.time_since_epoch().count());
    const fs::path dir = bin / "test_scratch" / "layouts" / (layout + "-" + key);
    if (fs::exists(dir / "gt" / "sim.json")) return dir;
    const fs::path staging = workDir() / ("writing-" + layout);
    fs::remove_all(staging);
    const std::string ids = layout == "kitti360" ? "ours" : "semantickitti";
    const std::string options =
        "--frames 4 --size 20 --seed 3 --cameras 2 --gt-views 0 "
        "--quiet --threads 2 --lidar-label-ids " +
        ids;
    std::vector<std::string> args{"street", "-o", staging.string(), "--layout", layout};
    std::istringstream words(options);
    for (std::string word; words >> word;) args.push_back(word);
    test::Child sim(test::kSimExe, args);
    const int code = sim.exitCode();
    INFO(sim.log());
    REQUIRE(code == 0);
    fs::create_directories(dir.parent_path());
    std::error_code error;
    fs::rename(staging, dir, error);  // fails if another process's copy is already there
    if (error) {
        fs::remove_all(staging);
        REQUIRE(fs::exists(dir / "gt" / "sim.json"));
    }
    return dir;
}

std::shared_ptr<Dataset> openLayout(const std::string& format, const fs::path& path) {
    DatasetConfig config;
    config.format = format;
    config.path = path.string();
    return Dataset::open(config);
}

/// Runs `vdbmap run <config> --set ... -o out` and returns its exit code; the log in `log`.
int runConfig(const std::string& config, const std::vector<std::string>& sets, const fs::path& out,
              std::string& log) {
    std::vector<std::string> args{"run", (fs::path(VDBMAP_SOURCE_DIR) / "config" / config).string(),
                                  "-o", out.string(), "--quiet"};
    for (const auto& s : sets) {
        args.push_back("--set");
        args.push_back(s);
    }
    test::Child child(test::kVdbmapExe, args);
    const int code = child.exitCode();
    log = child.log();
    UNSCOPED_INFO(log);
    return code;
}

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

/// LiDAR points of one frame that project into one camera's image, and how many of them
/// have the ground-truth class the simulator drew at their pixel.
struct Agreement {
    std::size_t seen = 0;
    std::size_t agree = 0;
    double fraction() const { return seen ? static_cast<double>(agree) / seen : 0.0; }
    Agreement& operator+=(const Agreement& o) {
        seen += o.seen;
        agree += o.agree;
        return *this;
    }
};

/// Agreement of frame i's points with camera c's KITTI-360 semantic image (KITTI-360 ids),
/// with the camera placed by `T_C_L`.
Agreement labelAgreement(const Dataset& dataset, const fs::path& root, std::size_t i, std::size_t c,
                         const Isometry3d& T_C_L) {
    const FrameInfo& frame = dataset.frame(i);
    const Camera& camera = dataset.cameras()[c];
    const PointCloud scan = readBin(frame.scan_path);  // labels belong to the points as stored
    const fs::path label_path = root / "gt" / "labels" / (frame.id + ".label");
    const LidarLabels labels = readLidarLabels(label_path);
    checkLabelCount(labels.size(), label_path, scan.size(), frame.scan_path);
    const cv::Mat drawn = readLabelImage(root / "data_2d_semantics" / "train" / kDrive /
                                         camera.name / "semantic" / (frame.id + ".png"));
    Agreement out;
    for (std::size_t k = 0; k < scan.size(); ++k) {
        Vec2d px;
        const Vec3d X_C = T_C_L * scan.points[k].cast<double>();
        if (!camera.intrinsics.project(X_C, px) || !camera.intrinsics.inside(px)) continue;
        const std::uint8_t ours = static_cast<std::uint8_t>(LidarLabels::classOf(labels.raw[k]));
        const int u = static_cast<int>(std::lround(px.x()));
        const int v = static_cast<int>(std::lround(px.y()));
        ++out.seen;
        out.agree += drawn.at<std::uint8_t>(v, u) == kitti360LabelId(ours) ? 1 : 0;
    }
    return out;
}

}  // namespace

TEST_CASE("KITTI-360 layout: a LiDAR point projects where the simulator drew it",
          "[io][dataset][kitti360][sim]") {
    const fs::path root = simulate("kitti360");
    const auto dataset = openLayout("kitti360", root);
    REQUIRE(dataset->numFrames() == 3);  // frame 1 has no pose
    CHECK(dataset->framesWithoutPose() == 1);
    CHECK(dataset->frame(1).id == "0000000002");
    REQUIRE(dataset->cameras().size() == 2);
    // Frames 0 and 2 (the last one, 3 m before the street's end, sees little but sky). Each
    // camera's chain is also checked without its rectifying rotation (~1 degree, ~14 px).
    Agreement chain, without_rect;
    for (std::size_t i = 0; i < 2; ++i) {
        for (std::size_t c = 0; c < 2; ++c) {
            INFO("frame " << dataset->frame(i).id << ", camera " << dataset->cameras()[c].name);
            const Isometry3d& T_C_L = dataset->cameras()[c].T_C_L;
            const Agreement a = labelAgreement(*dataset, root, i, c, T_C_L);
            Isometry3d R_rect = Isometry3d::Identity();
            R_rect.linear() = Eigen::AngleAxisd(c == 0 ? 0.02 : 0.015,
                                                c == 0 ? Vec3d(0.2, 1.0, 0.1).normalized()
                                                       : Vec3d(1.0, -0.3, 0.2).normalized())
                                  .toRotationMatrix();
            const Agreement b = labelAgreement(*dataset, root, i, c, R_rect.inverse() * T_C_L);
            CHECK(a.seen > 3000);
            // Points the LiDAR sees but the camera, 0.3-0.8 m away, does not: up to 17 % in
            // one view (the sim's own KITTI chain gives the same figure).
            CHECK(a.fraction() > 0.8);
            CHECK(b.fraction() < a.fraction() - 0.03);
            chain += a;
            without_rect += b;
        }
    }
    CHECK(chain.fraction() > 0.95);
    CHECK(without_rect.fraction() < chain.fraction() - 0.04);
}

TEST_CASE("The three downloaded layouts of one simulated drive read back the same frames",
          "[io][dataset][sim]") {
    const fs::path odometry = simulate("kitti-odometry") / "dataset" / "sequences" / "00";
    const fs::path semantic = simulate("semantic-kitti") / "dataset" / "sequences" / "00";
    const fs::path k360 = simulate("kitti360");
    const auto from_odometry = openLayout("kitti", odometry);
    const auto from_semantic = openLayout("kitti", semantic);
    const auto from_360 = openLayout("kitti360", k360);

    // The odometry download: poses found in dataset/poses/00.txt, both colour cameras.
    CHECK(from_odometry->posesPath() ==
          fs::absolute(odometry / ".." / ".." / "poses" / "00.txt").lexically_normal());
    CHECK(from_odometry->cameras().size() == 2);
    CHECK(from_odometry->lidarLabelDir().empty());
    // SemanticKITTI: poses in the sequence, labels, no camera.
    CHECK(from_semantic->posesPath() == semantic / "poses.txt");
    CHECK(from_semantic->cameras().empty());
    CHECK(from_semantic->lidarLabelPath(2).has_value());

    REQUIRE(from_odometry->numFrames() == 4);
    REQUIRE(from_semantic->numFrames() == 4);
    for (std::size_t i = 0; i < 4; ++i) {
        CHECK(from_semantic->frame(i).T_W_L.isApprox(from_odometry->frame(i).T_W_L, 1e-12));
        CHECK(test::readBytes(from_semantic->frame(i).scan_path) ==
              test::readBytes(from_odometry->frame(i).scan_path));
    }
    // KITTI-360 frames 0, 2 and 3: the same LiDAR pose through T_W_IMU, T_IMU_C0 and T_C0_L (1e-9:
    // the chain has five factors written with 17 digits).
    for (const auto& [i360, iodo] : {std::pair<std::size_t, std::size_t>{0, 0}, {1, 2}, {2, 3}}) {
        CHECK(from_360->frame(i360).T_W_L.isApprox(from_odometry->frame(iodo).T_W_L, 1e-9));
        CHECK(test::readBytes(from_360->frame(i360).scan_path) ==
              test::readBytes(from_odometry->frame(iodo).scan_path));
    }
    // Rectified KITTI-360 cameras 00 and 01 are the simulator's image_2 and image_3.
    for (std::size_t c = 0; c < 2; ++c) {
        CHECK(from_360->T_W_C(1, c).isApprox(from_odometry->T_W_C(2, c), 1e-9));
        CHECK(from_360->cameras()[c].intrinsics.fx == from_odometry->cameras()[c].intrinsics.fx);
    }
    CHECK(from_360->frame(1).timestamp_s == Approx(from_odometry->frame(2).timestamp_s));
}

TEST_CASE("vdbmap run maps each downloaded layout with its example config", "[io][dataset][cli]") {
    std::string log;
    SECTION("KITTI odometry: the poses found in dataset/poses/00.txt") {
        const fs::path sequence = simulate("kitti-odometry") / "dataset" / "sequences" / "00";
        const fs::path out = workDir() / "run_odometry";
        REQUIRE(runConfig("kitti_odometry.yaml",
                          {"dataset.path=" + sequence.string(), "integrate.atsdf.voxel_size_m=0.2"},
                          out, log) == 0);
        const nlohmann::json report = readJson(out / "report.json");
        const std::string poses = report["dataset"]["poses_file"];
        CHECK_THAT(poses, Contains((fs::path("dataset") / "poses" / "00.txt").string()));
        CHECK(report["counts"]["frames"] == 4);
        CHECK(readMeshPly(out / "mesh.ply").n_faces() > 1000);
    }
    SECTION("SemanticKITTI: a LiDAR-only semantic mesh") {
        const fs::path sequence = simulate("semantic-kitti") / "dataset" / "sequences" / "00";
        const fs::path out = workDir() / "run_semantic";
        REQUIRE(runConfig("semantic_kitti.yaml",
                          {"dataset.path=" + sequence.string(), "integrate.atsdf.voxel_size_m=0.2"},
                          out, log) == 0);
        std::vector<std::uint8_t> labels;
        const TriMesh mesh = readMeshPly(out / "semantic" / "mesh.ply", &labels);
        REQUIRE(labels.size() == mesh.n_faces());
        const auto road = std::count(labels.begin(), labels.end(), 0);
        const auto building = std::count(labels.begin(), labels.end(), 2);
        CHECK(road > static_cast<long>(labels.size() / 5));  // the street's road and buildings
        CHECK(building > static_cast<long>(labels.size() / 20));
        const nlohmann::json report = readJson(out / "report.json");
        CHECK(report["counts"]["cameras"] == 0);
    }
    SECTION("KITTI-360: both cameras texture the mesh, the scan without a pose is counted") {
        const fs::path root = simulate("kitti360");
        const fs::path out = workDir() / "run_360";
        REQUIRE(runConfig("kitti360.yaml",
                          {"dataset.path=" + root.string(), "integrate.atsdf.voxel_size_m=0.2"},
                          out, log) == 0);
        const nlohmann::json report = readJson(out / "report.json");
        CHECK(report["counts"]["frames_without_pose"] == 1);
        CHECK(report["counts"]["frames"] == 3);
        CHECK(report["counts"]["cameras"] == 2);
        CHECK(report["dataset"]["drive"] == kDrive);
        CHECK(fs::exists(out / "textured" / "mesh.obj"));
    }
}

TEST_CASE("Bad downloaded layouts fail through vdbmap run with exit 1 and name the problem",
          "[io][dataset][cli]") {
    std::string log;
    const auto copy = [](const fs::path& from, const std::string& name) {
        const fs::path to = workDir() / name;
        fs::remove_all(to);
        fs::copy(from, to, fs::copy_options::recursive);
        return to;
    };
    SECTION("KITTI odometry without its poses names both places") {
        const fs::path root = copy(simulate("kitti-odometry"), "no_poses");
        fs::remove(root / "dataset" / "poses" / "00.txt");
        const fs::path sequence = root / "dataset" / "sequences" / "00";
        CHECK(runConfig("kitti_odometry.yaml", {"dataset.path=" + sequence.string()},
                        workDir() / "out_no_poses", log) == 1);
        CHECK_THAT(log, Contains((sequence / "poses.txt").string()) &&
                            Contains((fs::path("poses") / "00.txt").string()));
    }
    SECTION("a malformed pose line names file:line; too few poses name both counts") {
        const fs::path root = copy(simulate("kitti-odometry"), "bad_poses");
        const fs::path poses = root / "dataset" / "poses" / "00.txt";
        const std::string good = test::readBytes(poses);
        test::writeText(poses, good.substr(0, good.find('\n') + 1) + "1 2 3\n");
        const fs::path sequence = root / "dataset" / "sequences" / "00";
        CHECK(runConfig("kitti_odometry.yaml", {"dataset.path=" + sequence.string()},
                        workDir() / "out_bad_poses", log) == 1);
        CHECK_THAT(log, Contains("00.txt:2"));
        test::writeText(poses, good.substr(0, good.find('\n') + 1));
        CHECK(runConfig("kitti_odometry.yaml", {"dataset.path=" + sequence.string()},
                        workDir() / "out_few_poses", log) == 1);
        CHECK_THAT(log, Contains("has 1 poses") && Contains("has 4 scans"));
    }
    SECTION("a KITTI-360 calibration without a key names the key") {
        const fs::path root = copy(simulate("kitti360"), "no_key");
        const fs::path perspective = root / "calibration" / "perspective.txt";
        std::string text = test::readBytes(perspective);
        text.replace(text.find("R_rect_01"), 9, "R_rect_xx");
        test::writeText(perspective, text);
        CHECK(runConfig("kitti360.yaml", {"dataset.path=" + root.string()},
                        workDir() / "out_no_key", log) == 1);
        CHECK_THAT(log, Contains("perspective.txt") && Contains("'R_rect_01:'"));
    }
}
