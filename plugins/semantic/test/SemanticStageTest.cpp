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
