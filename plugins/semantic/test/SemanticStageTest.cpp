// SPDX-License-Identifier: Apache-2.0
// End to end: a short simulated street -> ATSDF -> mesh -> semantic.mrf loaded as a plugin.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <set>

#include "vdbmap/core/Log.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "support/SimRigFixture.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;

TEST_CASE("semantic.mrf labels a simulated street end to end", "[semantic][pipeline]") {
    vdbmap::setLogLevel(vdbmap::LogLevel::Warn);
    const fs::path root = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "semantic_stage";
    fs::remove_all(root);
    vdbmap::SimOptions sim;
    sim.frames = 4;
    sim.size_m = 20.0;
    sim.gt_views = 0;
    sim.label_noise_px = 2;
    sim.quiet = true;
    vdbmap::writeSimSequence(sim, root / "seq");

    const std::string plugin =
        (fs::path(VDBMAP_PLUGIN_BUILD_DIR) / "vdbmap_plugin_semantic.so").string();
    const std::string yaml = "dataset: {format: kitti, path: seq}\n"
                             "plugins: [\"" + plugin + "\"]\n"
                             "stages:\n"
                             "  - stage: integrate.atsdf\n"
                             "    voxel_size_m: 0.2\n"
                             "  - stage: mesh.marching_cubes\n"
                             "  - stage: semantic.mrf\n"
                             "    max_view_angle_deg: 88\n"
                             "    export_classes: [0]\n"
                             "    label_grid: true\n"
                             "output: {write_map: true, write_mesh: true}\n";
    auto pipeline = vdbmap::Pipeline::fromString(yaml, "semantic_stage_test", root);
    vdbmap::Report report;
    pipeline->run(root / "out", report, true);

    const fs::path out = root / "out";
    REQUIRE(fs::exists(out / "map.vdb"));
    REQUIRE(fs::exists(out / "semantic" / "mesh.obj"));
    REQUIRE(fs::exists(out / "semantic" / "mesh.mtl"));
    REQUIRE(fs::exists(out / "semantic" / "class_0_road.ply"));
    std::vector<std::uint8_t> labels;
    const auto mesh = vdbmap::readMeshPly(out / "semantic" / "mesh.ply", &labels);
    REQUIRE(labels.size() == mesh.n_faces());
    REQUIRE(mesh.n_faces() > 1000);
    std::size_t unknown = 0;
    std::set<int> classes;
    for (const auto id : labels) {
        unknown += id == vdbmap::kUnknownLabel;
        classes.insert(id);
    }
    REQUIRE(classes.count(0) == 1);  // road
    REQUIRE(classes.size() >= 3);
    // Only components that no camera saw stay unknown (4 frames, one forward camera).
    REQUIRE(unknown < mesh.n_faces() / 3);
    REQUIRE(report.getJson({"stages", "semantic.mrf", "unlabelled_faces"}) ==
            std::to_string(unknown));
    REQUIRE(report.getJson({"stages", "semantic.mrf", "faces"}) ==
            std::to_string(mesh.n_faces()));
    REQUIRE(report.getJson({"stages", "semantic.mrf", "classes", "0", "name"}) == "\"road\"");
}

namespace {

/// The pipeline YAML of a small surround-rig street (support/SimRigFixture.h) + `stages`.
std::string rigPipeline(const fs::path& root, const std::string& stages) {
    return vdbmap::test::rigDatasetYaml(root) + stages;
}

}  // namespace

TEST_CASE("semantic.mrf votes with every camera of a surround rig", "[semantic][pipeline][rig]") {
    vdbmap::setLogLevel(vdbmap::LogLevel::Warn);
    const fs::path root = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "semantic_rig";
    fs::remove_all(root);
    const std::string plugin =
        (fs::path(VDBMAP_PLUGIN_BUILD_DIR) / "vdbmap_plugin_semantic.so").string();
    const std::string yaml = rigPipeline(root, "plugins: [\"" + plugin +
                                                   "\"]\n"
                                                   "stages:\n"
                                                   "  - stage: integrate.atsdf\n"
                                                   "    voxel_size_m: 0.2\n"
                                                   "  - stage: mesh.marching_cubes\n"
                                                   "  - stage: semantic.mrf\n"
                                                   "    max_view_angle_deg: 88\n"
                                                   "    lambda: 0\n");
    // Naive voting (lambda 0) leaves every face no camera saw unknown. The world frame is
    // camera 0 of frame 0 (z forward): faces 3 m or more behind the first pose are only in
    // the rear camera's images.
    auto labelledBehind = [&](const std::vector<std::string>& overrides, const fs::path& out,
                              std::size_t& behind, vdbmap::Report& report) {
        auto pipeline = vdbmap::Pipeline::fromString(yaml, "semantic_rig_test", root, overrides);
        pipeline->run(out, report, true);
        std::vector<std::uint8_t> labels;
        const auto mesh = vdbmap::readMeshPly(out / "semantic" / "mesh.ply", &labels);
        std::size_t labelled = 0;
        behind = 0;
        for (const auto fh : mesh.faces()) {
            vdbmap::TriMesh::Point c(0, 0, 0);
            for (const auto vh : mesh.fv_range(fh)) c += mesh.point(vh);
            if (c[2] / 3.0f > -3.0f) continue;
            ++behind;
            labelled += labels[static_cast<std::size_t>(fh.idx())] != vdbmap::kUnknownLabel;
        }
        return labelled;
    };
    vdbmap::Report rig_report, front_report;
    std::size_t behind_rig = 0, behind_front = 0;
    const std::size_t rig = labelledBehind({}, root / "rig", behind_rig, rig_report);
    const std::size_t front = labelledBehind(
        {"dataset.cameras=[{name: front, image_dir: image_front, semantic_dir: semantic_front, "
         "calib_file: calib_front.txt}]"},
        root / "front", behind_front, front_report);
    REQUIRE(rig_report.getJson({"stages", "semantic.mrf", "views"}) == "16");
    REQUIRE(front_report.getJson({"stages", "semantic.mrf", "views"}) == "4");
    REQUIRE(behind_rig == behind_front);  // the same scans give the same mesh
    REQUIRE(behind_rig > 500);
    CHECK(front == 0);
    CHECK(rig > behind_rig * 8 / 10);
}
