// SPDX-License-Identifier: Apache-2.0
// The KITTI odometry download as is: dataset/sequences/NN/{velodyne, image_2, calib.txt,
// times.txt} with the poses apart, in dataset/poses/NN.txt (docs/DATA.md "KITTI odometry").
#include <catch2/catch.hpp>

#include "unit/KittiFixture.h"
#include "vdbmap/io/Dataset.h"

using namespace vdbmap;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

/// A KittiFixture at <dir>/dataset/sequences/07 with its poses moved to dataset/poses/07.txt.
struct DownloadFixture {
    fs::path sequence;
    fs::path download_poses;
    test::KittiFixture kitti;

    explicit DownloadFixture(const fs::path& dir)
        : sequence(dir / "dataset" / "sequences" / "07"),
          download_poses(dir / "dataset" / "poses" / "07.txt"),
          kitti(sequence) {
        fs::create_directories(download_poses.parent_path());
        fs::rename(sequence / "poses.txt", download_poses);
    }
};

std::shared_ptr<Dataset> openSequence(const std::string& path, const std::string& poses_file = {},
                                      const fs::path& base = {}) {
    DatasetConfig config;
    config.path = path;
    config.poses_file = poses_file;
    return Dataset::open(config, base);
}

/// T_W_L of every frame equals T_W_C0 * Tr of the fixture's poses.
void checkPoses(const Dataset& dataset, const test::KittiFixture& kitti) {
    REQUIRE(dataset.numFrames() == kitti.T_W_C0.size());
    for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
        CHECK(dataset.frame(i).T_W_L.isApprox(kitti.T_W_C0[i] * kitti.calib.Tr, 1e-12));
    }
}

}  // namespace

TEST_CASE("KITTI odometry download: the poses are found in dataset/poses/NN.txt",
          "[io][dataset][kitti]") {
    test::TempDir dir;
    const DownloadFixture fixture(dir.path());
    const auto dataset = openSequence(fixture.sequence.string());
    CHECK(dataset->posesPath() == fs::absolute(fixture.download_poses).lexically_normal());
    checkPoses(*dataset, fixture.kitti);
    CHECK(dataset->cameras().size() == 1);  // image_2 of the sequence folder
    CHECK(dataset->framesWithoutPose() == 0);

    SECTION("a trailing slash and a relative path find them too") {
        const auto relative = openSequence("dataset/sequences/07/", {}, dir.path());
        CHECK(fs::equivalent(relative->posesPath(), fixture.download_poses));
        checkPoses(*relative, fixture.kitti);
    }
    SECTION("SEQ/poses.txt, when present, is read first (SemanticKITTI keeps it there)") {
        std::vector<Isometry3d> shifted = fixture.kitti.T_W_C0;
        for (auto& T : shifted) T.translation().x() += 5.0;
        writeKittiPoses(fixture.sequence / "poses.txt", shifted);
        const auto in_sequence = openSequence(fixture.sequence.string());
        CHECK(in_sequence->posesPath() == fixture.sequence / "poses.txt");
        CHECK(in_sequence->frame(1).T_W_L.isApprox(shifted[1] * fixture.kitti.calib.Tr, 1e-12));
    }
    SECTION("poses_file names the file, relative to the sequence folder") {
        fs::rename(fixture.download_poses, dir / "elsewhere.txt");
        const auto explicit_file =
            openSequence(fixture.sequence.string(), "../../../elsewhere.txt");
        CHECK(fs::equivalent(explicit_file->posesPath(), dir / "elsewhere.txt"));
        checkPoses(*explicit_file, fixture.kitti);
        CHECK_THAT(
            test::ioErrorMessage([&] { openSequence(fixture.sequence.string(), "nope.txt"); }),
            Contains("poses_file not found") && Contains("nope.txt"));
    }
}

TEST_CASE("KITTI odometry download: bad poses are errors naming the places and lines",
          "[io][dataset][kitti]") {
    test::TempDir dir;
    const DownloadFixture fixture(dir.path());
    SECTION("neither SEQ/poses.txt nor dataset/poses/NN.txt") {
        fs::remove(fixture.download_poses);
        const std::string message =
            test::ioErrorMessage([&] { openSequence(fixture.sequence.string()); });
        CHECK_THAT(message, Contains((fixture.sequence / "poses.txt").string()) &&
                                Contains((fs::path("dataset") / "poses" / "07.txt").string()) &&
                                Contains("poses_file"));
    }
    SECTION("a malformed line names file:line") {
        test::writeText(fixture.download_poses, "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0\n");
        CHECK_THAT(test::ioErrorMessage([&] { openSequence(fixture.sequence.string()); }),
                   Contains("07.txt:2") && Contains("12"));
    }
    SECTION("fewer poses than scans names both counts") {
        writeKittiPoses(fixture.download_poses, {fixture.kitti.T_W_C0[0]});
        CHECK_THAT(test::ioErrorMessage([&] { openSequence(fixture.sequence.string()); }),
                   Contains("07.txt has 1 poses") && Contains("3 scans"));
    }
}
