// SPDX-License-Identifier: Apache-2.0
// The inputs that used to pass in silence (issue 15's table), each run through the built
// `vdbmap run` on a copy of a small simulated sequence: each must now be an error naming the
// file or key, the value found and what was expected, with the documented exit code.
// Also: a failed vdbmap-sim leaves no partial sequence folder.
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "support/CliRun.h"

using namespace vdbmap;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

fs::path workDir() {
    static const fs::path dir = [] {
        const fs::path d = test::freshProcessDir("vdbmap_badinput");
        test::writeSmallSequence(d / "seq_master");
        return d;
    }();
    static const test::RemoveAtExit cleanup{dir};
    return dir;
}

/// A fresh copy of the small sequence, to break.
fs::path copySequence(const std::string& name) {
    const fs::path dst = workDir() / name;
    fs::remove_all(dst);
    fs::copy(workDir() / "seq_master", dst, fs::copy_options::recursive);
    return dst;
}

fs::path writeConfig(const std::string& name, const fs::path& seq, const std::string& plugins,
                     const std::string& stages) {
    const fs::path path = workDir() / (name + ".yaml");
    std::ofstream(path) << "dataset: {format: kitti, path: " << seq.string() << "}\n"
                        << "plugins: [" << plugins << "]\n"
                        << "stages:\n"
                        << stages;
    return path;
}

const char* kMeshStages =
    "  - {stage: integrate.atsdf, voxel_size_m: 0.25}\n"
    "  - {stage: mesh.marching_cubes}\n";

int run(const fs::path& config, const std::string& out, std::string* log,
        const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{"run", config.string(), "-o", (workDir() / out).string(),
                                  "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    test::Child child(test::kVdbmapExe, args);
    const int code = child.exitCode();
    *log = child.log();
    UNSCOPED_INFO(child.log());
    return code;
}

}  // namespace

TEST_CASE("bad input: a voxel size below 1 mm is a config error naming key, value and minimum",
          "[cli][hardening]") {
    const fs::path config = writeConfig("voxel", workDir() / "seq_master", "", kMeshStages);
    std::string log;
    CHECK(run(config, "out_voxel", &log, {"--set", "integrate.atsdf.voxel_size_m=1e-9"}) == 2);
    CHECK_THAT(log, Contains("voxel_size_m") && Contains("1e-09") && Contains("0.001"));
    CHECK_THAT(log, !Contains("ArithmeticError"));
    // 1 mm itself is accepted (checked only: a 1 mm map of the street would be huge).
    CHECK(run(config, "out_voxel_ok", &log,
              {"--check", "--set", "integrate.atsdf.voxel_size_m=0.001"}) == 0);
}

TEST_CASE("bad input: an image of the wrong size names the file, its size and the expected one",
          "[cli][hardening]") {
    const fs::path seq = copySequence("seq_small_image");
    cv::imwrite((seq / "image_2" / "000001.png").string(), cv::Mat(5, 7, CV_8UC3, cv::Scalar(1)));
    const fs::path config = writeConfig("image_size", seq, "texture",
                                        std::string(kMeshStages) + "  - {stage: texture.mrf}\n");
    std::string log;
    CHECK(run(config, "out_image_size", &log) == 1);
    CHECK_THAT(log, Contains("000001.png") && Contains("7 x 5") && Contains("1242 x 375"));
    CHECK_THAT(log, Contains("image_2"));
}

TEST_CASE("bad input: texture image masks that are no folder, or of the wrong size, name it",
          "[cli][hardening][image_masks]") {
    const fs::path seq = workDir() / "seq_master";
    const fs::path config = writeConfig("image_masks", seq, "texture",
                                        std::string(kMeshStages) + "  - {stage: texture.mrf}\n");
    std::string log;
    const fs::path missing = workDir() / "no_such_masks";
    CHECK(run(config, "out_masks_missing", &log,
              {"--set", "texture.mrf.image_masks=" + missing.string()}) == 2);
    CHECK_THAT(log, Contains("image_masks") && Contains(missing.string()) &&
                        Contains("not a directory"));
    const fs::path masks = workDir() / "masks_small";
    fs::create_directories(masks);
    cv::imwrite((masks / "000001.png").string(), cv::Mat(5, 7, CV_8UC1, cv::Scalar(255)));
    CHECK(run(config, "out_masks_small", &log,
              {"--set", "texture.mrf.image_masks=" + masks.string()}) == 1);
    CHECK_THAT(log, Contains((masks / "000001.png").string()) && Contains("7 x 5") &&
                        Contains("1242 x 375"));
    CHECK(!fs::exists(workDir() / "out_masks_small" / "textured" / "mesh.obj"));
    // semantic.mrf reads masks by the same rule.
    const fs::path semantic = writeConfig("image_masks_semantic", seq, "semantic",
                                          std::string(kMeshStages) + "  - {stage: semantic.mrf}\n");
    CHECK(run(semantic, "out_masks_semantic_missing", &log,
              {"--set", "semantic.mrf.image_masks=" + missing.string()}) == 2);
    CHECK_THAT(log, Contains("semantic.mrf") && Contains("image_masks") &&
                        Contains(missing.string()));
    CHECK(run(semantic, "out_masks_semantic_small", &log,
              {"--set", "semantic.mrf.image_masks=" + masks.string()}) == 1);
    CHECK_THAT(log, Contains((masks / "000001.png").string()) && Contains("7 x 5"));
}

TEST_CASE("bad input: a 3-channel semantic image is an error saying one channel is needed",
          "[cli][hardening]") {
    const fs::path seq = copySequence("seq_rgb_semantic");
    const fs::path png = seq / "semantic_2" / "000001.png";
    const cv::Mat ids = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
    REQUIRE(ids.type() == CV_8UC1);
    cv::Mat rgb;
    cv::merge(std::vector<cv::Mat>{ids, ids, ids}, rgb);  // grey-looking, but 3 channels
    cv::imwrite(png.string(), rgb);
    const fs::path config = writeConfig("semantic_rgb", seq, "semantic",
                                        std::string(kMeshStages) + "  - {stage: semantic.mrf}\n");
    std::string log;
    CHECK(run(config, "out_semantic_rgb", &log) == 1);
    CHECK_THAT(log, Contains("000001.png") && Contains("3 channels") && Contains("one channel"));
}

TEST_CASE("bad input: a folder named like a scan is an error naming it", "[cli][hardening]") {
    const fs::path seq = copySequence("seq_bin_folder");
    fs::remove(seq / "velodyne" / "000001.bin");
    fs::create_directory(seq / "velodyne" / "000001.bin");
    const fs::path config = writeConfig("bin_folder", seq, "", kMeshStages);
    std::string log;
    CHECK(run(config, "out_bin_folder", &log) == 1);
    CHECK_THAT(log, Contains("000001.bin") && Contains("not a regular file"));
}

TEST_CASE("vdbmap-sim: a failed run leaves no sequence folder, a good one replaces its own",
          "[cli][hardening][sim]") {
    const fs::path out = workDir() / "sim_out";
    // Refused inside writeSimSequence, after the staging folder exists: it is removed.
    {
        test::Child child(test::kSimExe, {"street", "-o", out.string(), "--rig", "surround",
                                          "--cameras", "2", "-q"});
        CHECK(child.exitCode() == 2);
        CHECK_FALSE(fs::exists(out));
    }
    // Killed half-way: nothing at the final path, no staging folder once the next run is over.
    {
        // Long enough not to finish first; killed once its staging folder holds a scan.
        test::Child child(test::kSimExe, {"street", "-o", out.string(), "--frames", "400",
                                          "--size", "100", "--gt-views", "0"});
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        const fs::path first_scan = workDir() /
                                    (".sim_out.partial-" + std::to_string(child.pid())) /
                                    "velodyne" / "000000.bin";
        bool staging_seen = false;
        while (!staging_seen && std::chrono::steady_clock::now() < deadline) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            std::error_code ec;
            staging_seen = fs::exists(first_scan, ec);
        }
        CHECK(staging_seen);
        child.kill(SIGKILL);
        CHECK(child.exitCode() == -SIGKILL);
        CHECK_FALSE(fs::exists(out));
    }
    {
        test::Child child(test::kSimExe, {"street", "-o", out.string(), "--frames", "2",
                                          "--size", "20", "--no-images", "--gt-views", "0",
                                          "-q"});
        REQUIRE(child.exitCode() == 0);
        CHECK(fs::exists(out / "gt" / "sim.json"));
        CHECK(fs::exists(out / "velodyne" / "000001.bin"));
    }
    for (const auto& entry : fs::directory_iterator(workDir())) {
        CHECK_THAT(entry.path().filename().string(), !Contains(".sim_out."));
    }
    // A folder that is not a sequence is never replaced.
    const fs::path foreign = workDir() / "foreign";
    fs::create_directories(foreign);
    std::ofstream(foreign / "notes.txt") << "mine\n";
    test::Child child(test::kSimExe, {"street", "-o", foreign.string(), "--frames", "2",
                                      "--size", "20", "--no-images", "--gt-views", "0", "-q"});
    CHECK(child.exitCode() == 1);
    CHECK_THAT(child.log(), Contains("not a vdbmap-sim sequence"));
    CHECK(fs::exists(foreign / "notes.txt"));
}
