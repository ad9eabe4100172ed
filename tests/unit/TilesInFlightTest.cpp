// SPDX-License-Identifier: Apache-2.0
// Tiles in flight side by side (issue 37): a tiled run whose finished tiles' texture and
// semantic stages run as tasks beside the integration writes byte for byte the files of the
// run that finishes one tile after the other; the memory budget bounds the tiles in flight;
// a failing tile task fails the run naming the tile, and no tiles.json is written. The
// journal's order and the resume are covered by ResumeTest (which runs tiles in flight).
#include <catch2/catch.hpp>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "support/PluginPath.h"
#include "support/OutputCompare.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;
using namespace vdbmap;
using vdbmap::test::filesBelow;
using vdbmap::test::readText;
using vdbmap::test::vdbVoxels;

namespace {

std::string plugin(const char* name) { return test::builtPluginPath(name); }

/// 40 m of street in 8 frames, 6.4 m tiles: about a dozen tiles, most finished while scans come in.
std::string yaml(const std::string& tiling_extra, const std::string& semantic_extra = "") {
    return "dataset: {format: kitti, path: seq, min_range_m: 1.0, max_range_m: 20}\n"
           "plugins: [\"" + plugin("texture") + "\", \"" + plugin("semantic") + "\"]\n"
           "stages:\n"
           "  - stage: integrate.atsdf\n"
           "    voxel_size_m: 0.2\n"
           "  - stage: mesh.marching_cubes\n"
           "  - stage: texture.mrf\n"
           "    max_view_angle_deg: 85\n"
           "  - stage: semantic.mrf\n"
           "    max_view_angle_deg: 88\n" + semantic_extra +
           "tiling: {tile_size_m: 6.4, halo_m: 1, occluder_margin_m: 3, max_view_distance_m: 20" +
           tiling_extra + "}\n";
}

/// The street in a folder of the test case's own (ctest runs test cases in parallel).
fs::path streetRoot(const std::string& test) {
    setLogLevel(LogLevel::Warn);
    const fs::path r = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / ("tiles_in_flight_" + test);
    fs::remove_all(r);
    SimOptions sim;
    sim.frames = 8;
    sim.size_m = 40.0;
    sim.gt_views = 0;
    sim.quiet = true;
    writeSimSequence(sim, r / "seq");
    return r;
}

nlohmann::json run(const fs::path& root, const std::string& name, const std::string& tiling_extra) {
    fs::remove_all(root / name);
    Report report;
    Pipeline::fromString(yaml(tiling_extra), name, root)->run(root / name, report, true);
    return nlohmann::json::parse(report.toJson());
}

}  // namespace

TEST_CASE("Tiles in flight write the files of one tile after the other", "[tiles][pipeline][inflight][heavy]") {
    const fs::path root = streetRoot("same");
    const nlohmann::json one = run(root, "one", ", max_tiles_in_flight: 1");
    const nlohmann::json three = run(root, "three", ", max_tiles_in_flight: 3, memory_budget_gb: 64");
    // stream: false finishes every tile after the last scan: they are launched in a burst.
    const nlohmann::json burst =
        run(root, "burst", ", max_tiles_in_flight: 3, memory_budget_gb: 64, stream: false");
    // A budget below the process's own memory: one tile at a time, in tasks (one always runs).
    const nlohmann::json tight =
        run(root, "tight", ", max_tiles_in_flight: 3, memory_budget_gb: 0.001, stream: false");

    const auto expected = filesBelow(root / "one" / "tiles");
    REQUIRE(expected.size() > 20);
    for (const char* other : {"three", "burst", "tight"}) {
        INFO(other);
        const auto files = filesBelow(root / other / "tiles");
        CHECK(files.size() == expected.size());
        for (const auto& [file, bytes] : expected) {
            INFO(file);
            REQUIRE(files.count(file) == 1);
            CHECK(files.at(file) == bytes);
        }
        CHECK(readText(root / other / "tiles.json") == readText(root / "one" / "tiles.json"));
        CHECK(vdbVoxels(root / other / "map.vdb") == vdbVoxels(root / "one" / "map.vdb"));
    }
        for (const nlohmann::json* r : {&one, &three, &burst, &tight}) {
        CHECK((*r)["tiling"]["in_flight"]["most_tiles_in_flight"].get<int>() <=
              (*r)["tiling"]["in_flight"]["max_tiles_in_flight"].get<int>());
    }
    CHECK(one["tiling"]["in_flight"]["most_tiles_in_flight"] == 1);
    CHECK(three["tiling"]["in_flight"]["max_tiles_in_flight"] == 3);
    CHECK(burst["tiling"]["in_flight"]["most_tiles_in_flight"].get<int>() >= 2);
    CHECK(tight["tiling"]["in_flight"]["most_tiles_in_flight"] == 1);
    CHECK(tight["tiling"]["in_flight"]["launches_waited"].get<int>() > 0);
    CHECK(tight["tiling"]["in_flight"]["memory_budget_bytes"].get<double>() ==
          Approx(0.001 * 1024 * 1024 * 1024).epsilon(1e-6));
    // Each tile's estimate is in its report; a tile run alone also gets its own peak.
    for (const auto& [name, tile] : one["tiles"].items()) {
        INFO(name);
        CHECK(tile["memory_estimate_bytes"].get<double>() > 0.0);
        CHECK(tile.contains("memory_added_bytes"));
    }
}

TEST_CASE("A failing tile task fails the run naming the tile, without tiles.json",
          "[tiles][pipeline][inflight]") {
    const fs::path root = streetRoot("fail");
    fs::remove_all(root / "fail");
    // label_grid is refused in tiled runs: semantic.mrf fails in every tile's task.
    Report report;
    auto pipeline = Pipeline::fromString(
        yaml(", max_tiles_in_flight: 3, memory_budget_gb: 64, stream: false",
             "    label_grid: true\n"),
        "fail", root);
    std::string message;
    try {
        pipeline->run(root / "fail", report, true);
    } catch (const std::exception& e) {
        message = e.what();
    }
    INFO(message);
    CHECK(message.rfind("tile ", 0) == 0);
    CHECK(message.find("semantic.mrf") != std::string::npos);
    CHECK(message.find("label_grid") != std::string::npos);
    CHECK_FALSE(fs::exists(root / "fail" / "tiles.json"));
    const nlohmann::json r = nlohmann::json::parse(report.toJson());
    CHECK(r["status"]["state"] == "failed");
    CHECK(r["status"]["failed_at"].get<std::string>().rfind("tile ", 0) == 0);
}
