// SPDX-License-Identifier: Apache-2.0
// One visibility for texture.mrf and semantic.mrf (Context::keepVisibility/takeVisibility,
// render/VisibilityKey.h): the stage that runs second takes the first one's visibility when
// the inputs are the same, narrowed to its own view angle, and writes what it writes when it
// computes its own.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "pipeline/ContextBuilder.h"
#include "support/OutputCompare.h"
#include "support/PluginPath.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/render/VisibilityKey.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;
using namespace vdbmap;

namespace {

/// A visibility of one face seen by views at the given cos_angle values, and a scan that hid
/// observations at `hidden_cos`.
SharedVisibility sharedOf(const std::vector<float>& cos_angles, const std::vector<float>& hidden_cos,
                          double angle_deg) {
    SharedVisibility s;
    s.visibility.offsets = {0, cos_angles.size()};
    for (std::size_t v = 0; v < cos_angles.size(); ++v) {
        FaceObservation o;
        o.view = static_cast<std::uint32_t>(v);
        o.cos_angle = cos_angles[v];
        s.visibility.obs.push_back(o);
    }
    s.scan_hidden_cos = hidden_cos;
    s.max_view_angle_deg = angle_deg;
    return s;
}

std::string streetYaml(bool semantic_first, const std::string& tiling) {
    const std::string texture = "  - stage: texture.mrf\n    max_view_angle_deg: 85\n";
    const std::string semantic = "  - stage: semantic.mrf\n    max_view_angle_deg: 88\n";
    return "dataset: {format: kitti, path: seq, min_range_m: 1.0}\n"
           "plugins: [\"" + test::builtPluginPath("texture") + "\", \"" +
           test::builtPluginPath("semantic") + "\"]\n"
           "stages:\n"
           "  - stage: integrate.atsdf\n"
           "    voxel_size_m: 0.2\n"
           "  - stage: mesh.marching_cubes\n" +
           (semantic_first ? semantic + texture : texture + semantic) + tiling;
}

/// Every file below `dir` (relative path -> content); report.json, the journal and map.vdb (a new
/// file UUID per write; the map comes before the stages) left out.
std::map<std::string, std::string> outputs(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        const std::string name = e.path().filename().string();
        if (name == "report.json" || name == "journal.jsonl" || name == "map.vdb") continue;
        out[fs::relative(e.path(), dir).string()] = test::readText(e.path());
    }
    return out;
}

}  // namespace

TEST_CASE("narrowViewAngle keeps the observations within the angle, in their order",
          "[visibility][shared]") {
    const float c80 = static_cast<float>(std::cos(80.0 * M_PI / 180.0));
    SharedVisibility s = sharedOf({0.9f, 0.05f, c80, 0.3f, 0.02f}, {0.04f, 0.5f}, 88.0);
    narrowViewAngle(s, 80.0);
    // computeVisibility's own test: kept iff cos_angle >= cos(80 deg) (float against double).
    std::vector<std::uint32_t> views;
    for (const auto& o : s.visibility.obs) views.push_back(o.view);
    const bool c80_kept = !(c80 < std::cos(80.0 * M_PI / 180.0));
    CHECK(views == (c80_kept ? std::vector<std::uint32_t>{0, 2, 3} : std::vector<std::uint32_t>{0, 3}));
    CHECK(s.visibility.offsets.back() == s.visibility.obs.size());
    CHECK(s.scan_hidden_cos == std::vector<float>{0.5f});
    CHECK(s.max_view_angle_deg == 80.0);
    CHECK_THROWS_AS(narrowViewAngle(s, 85.0), InvalidInput);  // wider than it was computed with
    CHECK_THROWS_AS(narrowViewAngle(s, 0.0), InvalidInput);
}

TEST_CASE("Context keeps a visibility for the next stage that asks for the same",
          "[visibility][shared]") {
    Report report;
    Context ctx(fs::temp_directory_path(), report, true);
    SECTION("the same key and a narrower angle: taken once, narrowed") {
        ctx.keepVisibility("k", sharedOf({0.9f, 0.01f}, {}, 88.0));
        const auto taken = ctx.takeVisibility("k", 85.0);
        REQUIRE(taken);
        CHECK(taken->visibility.obs.size() == 1);
        CHECK(taken->max_view_angle_deg == 85.0);
        CHECK_FALSE(ctx.takeVisibility("k", 85.0));
    }
    SECTION("another key or a wider angle: nothing, and the kept one is dropped") {
        ctx.keepVisibility("k", sharedOf({0.9f}, {}, 85.0));
        CHECK_FALSE(ctx.takeVisibility("k", 88.0));
        CHECK_FALSE(ctx.takeVisibility("k", 80.0));
        ctx.keepVisibility("k", sharedOf({0.9f}, {}, 85.0));
        CHECK_FALSE(ctx.takeVisibility("other", 85.0));
        CHECK_FALSE(ctx.takeVisibility("k", 85.0));
    }
    SECTION("kept until the end of the stage after the one that kept it") {
        ctx.keepVisibility("k", sharedOf({0.9f}, {}, 85.0));
        ContextBuilder::stageEnded(ctx);  // the keeper
        CHECK(ctx.takeVisibility("k", 85.0));
        ctx.keepVisibility("k", sharedOf({0.9f}, {}, 85.0));
        ContextBuilder::stageEnded(ctx);  // the keeper
        ContextBuilder::stageEnded(ctx);  // a stage that did not ask
        CHECK_FALSE(ctx.takeVisibility("k", 85.0));
    }
}

TEST_CASE("semantic.mrf before texture.mrf: texture takes its visibility and writes the same files",
          "[visibility][shared][pipeline]") {
    setLogLevel(LogLevel::Warn);
    const fs::path root = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "shared_visibility";
    if (!fs::exists(root / "seq" / "calib.txt")) {
        fs::remove_all(root);
        SimOptions sim;
        sim.frames = 6;
        sim.size_m = 36.0;
        sim.gt_views = 0;
        sim.quiet = true;
        sim.traffic = 1;  // movers, so that the scan test hides observations
        writeSimSequence(sim, root / "seq");
    }
    const std::string tiling = GENERATE(
        std::string(), std::string("tiling: {tile_size_m: 12.8, halo_m: 2, max_view_distance_m: 200}\n"));
    INFO(tiling);
    Report own_report, shared_report;
    fs::remove_all(root / "own");
    fs::remove_all(root / "shared");
    Pipeline::fromString(streetYaml(false, tiling), "own", root)->run(root / "own", own_report, true);
    Pipeline::fromString(streetYaml(true, tiling), "shared", root)
        ->run(root / "shared", shared_report, true);

    // What the texture stage reported in each run (per tile in a tiled run).
    const auto reused = [](const fs::path& dir) {
        std::vector<nlohmann::json> stages;
        std::ifstream in(dir / "report.json");
        const nlohmann::json r = nlohmann::json::parse(in);
        if (r.contains("tiles")) {
            for (const auto& [name, t] : r["tiles"].items()) {
                if (t["stages"].contains("texture.mrf")) stages.push_back(t["stages"]["texture.mrf"]);
            }
        } else {
            stages.push_back(r["stages"]["texture.mrf"]);
        }
        return stages;
    };
    const auto own = reused(root / "own"), shared = reused(root / "shared");
    REQUIRE(!own.empty());
    REQUIRE(own.size() == shared.size());
    std::size_t hidden = 0;
    for (std::size_t i = 0; i < own.size(); ++i) {
        if (own[i].contains("skipped")) continue;
        CHECK(own[i]["visibility_reused"] == false);
        CHECK(shared[i]["visibility_reused"] == true);
        // The scan test's count of the narrowed visibility is the texture stage's own.
        CHECK(shared[i]["scan_hidden_observations"] == own[i]["scan_hidden_observations"]);
        CHECK(shared[i]["observations"] == own[i]["observations"]);
        hidden += own[i]["scan_hidden_observations"].get<std::size_t>();
    }
    CHECK(hidden > 0);
    const auto a = outputs(root / "own"), b = outputs(root / "shared");
    REQUIRE(a.size() > 3);
    CHECK(a.size() == b.size());
    for (const auto& [path, content] : a) {
        INFO(path);
        REQUIRE(b.count(path));
        CHECK(b.at(path) == content);
    }
}
