// SPDX-License-Identifier: Apache-2.0
// semantic.mrf with per-point LiDAR labels end to end: a short simulated street (labels in
// SemanticKITTI ids, no images), the built-in map, and the errors for bad label input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

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

using Corner = std::array<float, 3>;
using FaceKey = std::array<Corner, 3>;

/// Each face of a semantic PLY by its corners (rotated to start at the smallest) -> label.
std::map<FaceKey, int> facesWithLabels(const fs::path& ply) {
    std::vector<std::uint8_t> labels;
    const TriMesh mesh = readMeshPly(ply, &labels);
    std::map<FaceKey, int> out;
    for (const auto fh : mesh.faces()) {
        FaceKey f{};
        std::size_t k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            const auto p = mesh.point(vh);
            f[k++] = {p[0], p[1], p[2]};
        }
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        out.emplace(f, labels[static_cast<std::size_t>(fh.idx())]);
    }
    return out;
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

/// A fresh folder test_scratch/<name> with a simulated street of `frames` LiDAR frames with
/// labels (no images) in <name>/seq.
fs::path simLabelledStreet(const std::string& name, std::size_t frames, double size_m) {
    setLogLevel(LogLevel::Warn);
    const fs::path root = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / name;
    fs::remove_all(root);
    SimOptions sim;
    sim.frames = frames;
    sim.size_m = size_m;
    sim.gt_views = 0;
    sim.images = false;
    sim.quiet = true;
    writeSimSequence(sim, root / "seq");
    return root;
}

}  // namespace

TEST_CASE("semantic.mrf labels a street from LiDAR labels alone; bad label input is an error",
          "[semantic][pipeline][lidar]") {
    const fs::path root = simLabelledStreet("lidar_label_stage", 3, 20.0);
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

TEST_CASE("semantic.mrf in tiles reads only the labelled scans that reach the tile",
          "[semantic][pipeline][lidar][tiles]") {
    const std::size_t frames = 8;
    const fs::path root = simLabelledStreet("lidar_label_tiles", frames, 40.0);
    // A 15 m sensor range: 8 m tiles far along the street cannot be reached by the first scans.
    std::string yaml = pipelineYaml("    label_map: semantickitti\n");
    yaml.replace(yaml.find("path: seq}"), 10, "path: seq, max_range_m: 15}");
    auto untiled = Pipeline::fromString(yaml, "untiled", root);
    Report untiled_report;
    untiled->run(root / "untiled", untiled_report, true);
    auto tiled = Pipeline::fromString(
        yaml + "tiling: {tile_size_m: 8, halo_m: 2, occluder_margin_m: 4}\n", "tiled", root);
    Report tiled_report;
    tiled->run(root / "tiled", tiled_report, true);

    const auto reference = facesWithLabels(root / "untiled" / "semantic" / "mesh.ply");
    const nlohmann::json tiles = nlohmann::json::parse(tiled_report.getJson({"tiles"}));
    REQUIRE(tiles.size() >= 4);
    std::size_t faces = 0, same = 0, tiles_skipping_scans = 0;
    for (const auto& [name, figures] : tiles.items()) {
        INFO("tile " << name);
        const auto& stage = figures["stages"]["semantic.mrf"];
        // Every frame is read or skipped as out of reach, none lost.
        CHECK(stage["lidar_scans"].get<std::size_t>() +
                  stage["lidar_scans_out_of_reach"].get<std::size_t>() ==
              frames);
        tiles_skipping_scans += stage["lidar_scans_out_of_reach"].get<std::size_t>() > 0;
        for (const auto& [face, label] :
             facesWithLabels(root / "tiled" / "tiles" / name / "semantic" / "mesh.ply")) {
            const auto it = reference.find(face);
            REQUIRE(it != reference.end());
            ++faces;
            same += it->second == label;
        }
    }
    CHECK(tiles_skipping_scans > 0);
    CHECK(faces == reference.size());
    // The tiles' MRFs see core + halo only, so a few labels near tile borders may differ.
    CHECK(static_cast<double>(same) >= 0.99 * static_cast<double>(faces));
}
