// SPDX-License-Identifier: Apache-2.0
// semantic.mrf with per-point LiDAR labels end to end: a short simulated street (labels in
// SemanticKITTI ids, no images), the built-in map, and the errors for bad label input.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;
using namespace vdbmap;

namespace {

std::string pipelineYaml(const std::string& semantic_options) {
    const std::string plugin =
        (fs::path(VDBMAP_PLUGIN_BUILD_DIR) / "vdbmap_plugin_semantic.so").string();
    return "dataset: {format: kitti, path: seq}\n"
           "plugins: [\"" + plugin + "\"]\n"
           "stages:\n"
           "  - stage: integrate.atsdf\n"
           "    voxel_size_m: 0.2\n"
           "  - stage: mesh.marching_cubes\n"
           "  - stage: semantic.mrf\n"
           "    image_votes: false\n"
           "    lidar_labels: true\n"
           "    lidar_vote_radius_m: 0.25\n" +
           semantic_options;
}

std::string runError(const fs::path& root, const std::string& yaml) {
    Report report;
    try {
        auto pipeline = Pipeline::fromString(yaml, "lidar_label_stage_test", root);
        pipeline->run(root / "out_bad", report, true);
    } catch (const ConfigError& e) {
        return std::string("ConfigError: ") + e.what();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST_CASE("semantic.mrf labels a street from LiDAR labels alone; bad label input is an error",
          "[semantic][pipeline][lidar]") {
    setLogLevel(LogLevel::Warn);
    const fs::path root = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "lidar_label_stage";
    fs::remove_all(root);
    SimOptions sim;
    sim.frames = 3;
    sim.size_m = 20.0;
    sim.gt_views = 0;
    sim.images = false;
    sim.quiet = true;
    writeSimSequence(sim, root / "seq");
    REQUIRE(fs::exists(root / "seq" / "labels" / "000002.label"));

    // Without the map the SemanticKITTI ids (40, 48, ...) are not ours: an error naming the
    // label file and the first unknown id.
    const std::string no_map = runError(root, pipelineYaml(""));
    CHECK_THAT(no_map, Catch::Contains("000000.label") && Catch::Contains("not in the label map"));

    auto pipeline = Pipeline::fromString(pipelineYaml("    label_map: semantickitti\n"),
                                         "lidar_label_stage_test", root);
    Report report;
    pipeline->run(root / "out", report, true);
    std::vector<std::uint8_t> labels;
    const TriMesh mesh = readMeshPly(root / "out" / "semantic" / "mesh.ply", &labels);
    REQUIRE(mesh.n_faces() > 1000);
    std::size_t unknown = 0, road = 0;
    for (const auto id : labels) {
        unknown += id == kUnknownLabel;
        road += id == 0;
    }
    CHECK(road > mesh.n_faces() / 5);  // the street is mostly road
    CHECK(report.getJson({"stages", "semantic.mrf", "lidar_scans"}) == "3");
    CHECK(report.getJson({"stages", "semantic.mrf", "views"}) == "0");
    CHECK(report.getJson({"stages", "semantic.mrf", "sources", "images", "faces"}) == "0");
    CHECK(report.getJson({"stages", "semantic.mrf", "unlabelled_faces"}) == std::to_string(unknown));
    // The PLY carries the confidence (float face property) after label and colour.
    {
        std::ifstream in(root / "out" / "semantic" / "mesh.ply", std::ios::binary);
        std::string header, line;
        while (std::getline(in, line) && line != "end_header") header += line + "\n";
        CHECK_THAT(header, Catch::Contains("property uchar label\nproperty uchar red\nproperty "
                                           "uchar green\nproperty uchar blue\nproperty float "
                                           "confidence\n"));
    }

    // A label file one entry short: both files and both counts.
    const fs::path label1 = root / "seq" / "labels" / "000001.label";
    LidarLabels one = readLidarLabels(label1);
    const std::size_t points = one.size();
    one.raw.pop_back();
    writeLidarLabels(label1, one);
    const std::string short_file =
        runError(root, pipelineYaml("    label_map: semantickitti\n"));
    CHECK_THAT(short_file, Catch::Contains("000001.label") && Catch::Contains("000001.bin") &&
                               Catch::Contains(std::to_string(points - 1) + " labels") &&
                               Catch::Contains(std::to_string(points) + " points"));
    one.raw.push_back(40);
    writeLidarLabels(label1, one);

    // A map file without road (40): the label file, the map file and the id.
    const fs::path map_file = root / "partial_map.txt";
    {
        std::ofstream out(map_file);
        out << "0 255\n48 1\n50 2\n";
    }
    const std::string partial =
        runError(root, pipelineYaml("    label_map: " + map_file.string() + "\n"));
    CHECK_THAT(partial, Catch::Contains(".label") && Catch::Contains("partial_map.txt") &&
                            Catch::Contains("(3 ids)"));

    // Option checks (exit 2) and a dataset without labels (exit 1).
    std::string no_source = pipelineYaml("");
    const std::string on = "    lidar_labels: true\n";
    no_source.replace(no_source.find(on), on.size(), "    lidar_labels: false\n");
    CHECK_THAT(runError(root, no_source), Catch::Contains("ConfigError") &&
                                              Catch::Contains("no source"));
    CHECK_THAT(runError(root, pipelineYaml("    fill: nearest\n")), Catch::Contains("ConfigError"));
    fs::rename(root / "seq" / "labels", root / "seq" / "labels_off");
    CHECK_THAT(runError(root, pipelineYaml("    label_map: semantickitti\n")),
               Catch::Contains("no LiDAR labels"));
    fs::rename(root / "seq" / "labels_off", root / "seq" / "labels");
}
