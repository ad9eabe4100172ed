// SPDX-License-Identifier: Apache-2.0
// semantic.mrf `image_masks`: a view does not vote for a face that touches its image's mask
// (vdbmap/render/ImageMasks.h, the rule texture.mrf uses).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "support/OutputCompare.h"
#include "support/PluginPath.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;
using namespace vdbmap;

namespace {

fs::path root() {
    static const fs::path r = [] {
        setLogLevel(LogLevel::Warn);
        const fs::path dir = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "semantic_image_masks";
        fs::remove_all(dir);
        SimOptions sim;
        sim.frames = 5;
        sim.size_m = 36.0;
        sim.gt_views = 0;
        sim.quiet = true;
        writeSimSequence(sim, dir / "seq");
        // Masks of every colour image: all zero, and all set.
        for (const auto& e : fs::directory_iterator(dir / "seq" / "image_2")) {
            const cv::Mat image = cv::imread(e.path().string());
            fs::create_directories(dir / "zeros");
            fs::create_directories(dir / "ones");
            cv::imwrite((dir / "zeros" / e.path().filename()).string(),
                        cv::Mat(image.size(), CV_8UC1, cv::Scalar(0)));
            cv::imwrite((dir / "ones" / e.path().filename()).string(),
                        cv::Mat(image.size(), CV_8UC1, cv::Scalar(255)));
        }
        return dir;
    }();
    return r;
}

nlohmann::json run(const std::string& name, const std::string& masks) {
    const std::string yaml =
        "dataset: {format: kitti, path: seq, min_range_m: 1.0}\n"
        "plugins: [\"" + test::builtPluginPath("semantic") + "\"]\n"
        "stages:\n"
        "  - stage: integrate.atsdf\n"
        "    voxel_size_m: 0.2\n"
        "  - stage: mesh.marching_cubes\n"
        "  - stage: semantic.mrf\n" +
        (masks.empty() ? "" : "    image_masks: " + (root() / masks).string() + "\n");
    Report report;
    const fs::path out = root() / ("out_" + name);
    fs::remove_all(out);
    Pipeline::fromString(yaml, name, root())->run(out, report, true);
    std::ifstream in(out / "report.json");
    return nlohmann::json::parse(in)["stages"]["semantic.mrf"];
}

}  // namespace

TEST_CASE("semantic image masks: empty masks change nothing, full masks leave no image vote",
          "[semantic][image_masks]") {
    const nlohmann::json none = run("none", "");
    const nlohmann::json zeros = run("zeros", "zeros");
    const nlohmann::json ones = run("ones", "ones");
    REQUIRE(none["observations"].get<std::size_t>() > 1000);
    CHECK(zeros["masked_observations"] == 0);
    CHECK(zeros["observations"] == none["observations"]);
    CHECK(test::readText(root() / "out_zeros" / "semantic" / "mesh.ply") ==
          test::readText(root() / "out_none" / "semantic" / "mesh.ply"));
    // Every observation touches a masked pixel: all go, and no face gets an image vote.
    CHECK(ones["masked_observations"] == none["observations"]);
    CHECK(ones["observations"] == 0);
    CHECK(ones["votes"] == 0);
}
