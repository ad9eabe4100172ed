// SPDX-License-Identifier: Apache-2.0
// Tiles in flight side by side (issue 37): a tiled run whose finished tiles' texture and
// semantic stages run as tasks beside the integration writes byte for byte the files of the
// run that finishes one tile after the other; the memory budget bounds the tiles in flight;
// a failing tile task fails the run naming the tile, and no tiles.json is written. The
// journal's order and the resume are covered by ResumeTest (which runs tiles in flight). A
// tile whose estimated peak exceeds the budget is worked in pieces with the tile's surface.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>

#include "pipeline/TileStream.h"
#include "support/PluginPath.h"
#include "support/OutputCompare.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/MeshIO.h"
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

/// `vdbmap run --resume` into the folder of an earlier run.
nlohmann::json resume(const fs::path& root, const std::string& name, const std::string& tiling_extra) {
    Report report;
    auto pipeline = Pipeline::fromString(yaml(tiling_extra), name, root);
    pipeline->setResume(true);
    pipeline->run(root / name, report, true);
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

TEST_CASE("The budget counts the map's growth since the memory without tiles was sampled",
          "[tiles][inflight]") {
    // Tiles in flight from the first launch on: the base (here 100 + the map's growth, as the
    // RSS would be) is sampled at the first launch only. The second launch fits the budget on
    // that sample (100 + 400 + 400 <= 1000) but not once the map has grown by 300 since: it
    // waits for the first task to end (and samples the base again, none being in flight).
    for (const std::size_t growth_after : {std::size_t(0), std::size_t(300)}) {
        INFO("growth " << growth_after);
        std::atomic<std::size_t> growth{0};
        std::atomic<bool> release{false}, first_ended{false};
        detail::TileTasks tasks(2, 1000, [&] { return 100 + growth.load(); }, [&] { return growth.load(); });
        tasks.launch(400, [&](std::string&) {
            while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
            first_ended = true;
        });
        growth = growth_after;
        std::thread releaser([&] {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            release = true;
        });
        tasks.launch(400, [](std::string&) {});
        const bool waited_for_first = first_ended;
        releaser.join();
        tasks.waitAll();
        const detail::TileTasks::Figures f = tasks.figures();
        CHECK(f.base_samples == (growth_after > 0 ? std::vector<std::size_t>{100, 400}
                                                  : std::vector<std::size_t>{100}));
        REQUIRE(f.at_launch.size() == 2);
        CHECK(f.at_launch[1][4] == 100 + growth_after);  // the base the budget counted
        CHECK(f.waits == (growth_after > 0 ? 1u : 0u));
        CHECK(waited_for_first == (growth_after > 0));
        CHECK(f.max_in_flight == (growth_after > 0 ? 1u : 2u));
    }
}

namespace {

using Face = std::array<std::array<float, 3>, 3>;

/// The faces of a mesh file as rotated corner triples (orientation kept).
std::set<Face> meshFaces(const fs::path& ply) {
    const TriMesh mesh = readMeshPly(ply);
    std::set<Face> out;
    for (const auto fh : mesh.faces()) {
        Face f{};
        std::size_t k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            const auto p = mesh.point(vh);
            f[k++] = {p[0], p[1], p[2]};
        }
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        REQUIRE(out.insert(f).second);  // no face twice
    }
    return out;
}

}  // namespace

TEST_CASE("A tile whose estimated peak exceeds the budget is worked in pieces",
          "[tiles][pipeline][inflight][split][heavy]") {
    const fs::path root = streetRoot("split");
    // Every tile whole (the budget far above any estimate), one after the other.
    const nlohmann::json whole = run(root, "whole", ", max_tiles_in_flight: 1, memory_budget_gb: 64");
    std::size_t largest = 0;
    for (const auto& [name, tile] : whole["tiles"].items()) {
        largest = std::max(largest, tile["memory_estimate_bytes"].get<std::size_t>());
    }
    // A budget just below the largest tile's estimate (and above the estimate's fixed part,
    // which no piece can go below): that tile, and any as large, must be split.
    const double budget_gb = static_cast<double>(largest - (512u << 10)) / (1024.0 * 1024.0 * 1024.0);
    REQUIRE(largest > detail::estimateTilePeakBytes(0, 0, 0) + (512u << 10));
    char budget_text[64];
    std::snprintf(budget_text, sizeof(budget_text), "%.9f", budget_gb);
    const std::string budget = std::string(", memory_budget_gb: ") + budget_text;
    const nlohmann::json one = run(root, "split_one", ", max_tiles_in_flight: 1" + budget);
    const nlohmann::json three = run(root, "split_three", ", max_tiles_in_flight: 3" + budget);
    const std::size_t budget_bytes = one["tiling"]["in_flight"]["memory_budget_bytes"];
    CHECK(budget_bytes < largest);

    // The plan states each split: the estimate over the budget and the pieces.
    std::set<std::string> split;
    for (const auto& planned : one["tiling"]["plan"]) {
        const std::string name = planned["name"];
        const bool over = whole["tiles"].contains(name) &&
                          whole["tiles"][name]["memory_estimate_bytes"].get<std::size_t>() > budget_bytes;
        INFO("tile " << name);
        CHECK(planned.contains("pieces") == over);
        if (!over) continue;
        split.insert(name);
        CHECK(planned["split_estimate_bytes"] == whole["tiles"][name]["memory_estimate_bytes"]);
        CHECK(planned["pieces"].size() >= 2);
    }
    REQUIRE_FALSE(split.empty());
    CHECK(one["tiling"]["split_tiles"].get<std::size_t>() == split.size());

    // Each piece fits the budget, and the pieces' core faces are the tile's, face for face.
    std::map<std::string, std::set<Face>> pieces_faces;
    for (const auto& [name, tile] : one["tiles"].items()) {
        INFO("tile " << name);
        if (!tile.contains("piece_of")) {
            CHECK(split.count(name) == 0);
            continue;
        }
        const std::string of = tile["piece_of"];
        CHECK(split.count(of) == 1);
        CHECK(name.rfind(of + ".", 0) == 0);
        CHECK(tile["memory_estimate_bytes"].get<std::size_t>() <= budget_bytes);
        for (const Face& f : meshFaces(root / "split_one" / "tiles" / name / "mesh.ply")) {
            CHECK(pieces_faces[of].insert(f).second);  // one piece owns a face
        }
    }
    for (const std::string& name : split) {
        INFO("tile " << name);
        CHECK_FALSE(fs::exists(root / "split_one" / "tiles" / name));
        CHECK(pieces_faces[name] == meshFaces(root / "whole" / "tiles" / name / "mesh.ply"));
    }
    // The tiles that were not split are those of the unsplit run, byte for byte.
    const auto whole_files = filesBelow(root / "whole" / "tiles");
    const auto one_files = filesBelow(root / "split_one" / "tiles");
    for (const auto& [file, bytes] : whole_files) {
        if (split.count(file.substr(0, file.find('/')))) continue;
        INFO(file);
        REQUIRE(one_files.count(file) == 1);
        CHECK(one_files.at(file) == bytes);
    }
    // Tiles in flight: the split run's files again, byte for byte.
    const auto three_files = filesBelow(root / "split_three" / "tiles");
    CHECK(three_files.size() == one_files.size());
    for (const auto& [file, bytes] : one_files) {
        INFO(file);
        REQUIRE(three_files.count(file) == 1);
        CHECK(three_files.at(file) == bytes);
    }
    CHECK(readText(root / "split_three" / "tiles.json") == readText(root / "split_one" / "tiles.json"));
    CHECK(vdbVoxels(root / "split_one" / "map.vdb") == vdbVoxels(root / "whole" / "map.vdb"));
    CHECK(three["tiling"]["split_tiles"] == one["tiling"]["split_tiles"]);

    // A resume with the same budget keeps every piece (the journal sees pieces as tiles), and
    // the files stay those of the split run.
    const nlohmann::json again = resume(root, "split_three", ", max_tiles_in_flight: 3" + budget);
    CHECK(again["resume"]["redone"] == 0);
    CHECK(again["resume"]["new"] == 0);
    std::set<std::string> kept;
    for (const auto& [name, decision] : again["resume"]["tiles"].items()) {
        if (decision["action"] == "kept") kept.insert(name);
    }
    for (const auto& [name, tile] : one["tiles"].items()) {
        INFO("tile " << name);
        CHECK(kept.count(name) == 1);  // pieces (named <ix>_<iy>.<piece>) among them
    }
    CHECK(filesBelow(root / "split_three" / "tiles") == one_files);
    CHECK(readText(root / "split_three" / "tiles.json") == readText(root / "split_one" / "tiles.json"));
    // A resume with a budget above every estimate works the split tiles whole: it keeps the
    // others, and ends with the unsplit run's files, the pieces' folders gone.
    const nlohmann::json wider = resume(root, "split_three", ", max_tiles_in_flight: 3, memory_budget_gb: 64");
    CHECK(wider["resume"]["redone"] == 0);
    CHECK(wider["resume"]["new"].get<std::size_t>() == split.size());
    CHECK(wider["tiling"]["split_tiles"] == 0);
    CHECK(filesBelow(root / "split_three" / "tiles") == whole_files);
    CHECK(readText(root / "split_three" / "tiles.json") == readText(root / "whole" / "tiles.json"));
}
