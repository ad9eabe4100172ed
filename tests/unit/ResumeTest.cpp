// SPDX-License-Identifier: Apache-2.0
// `vdbmap run --resume` (issue 36), with the built binary on a 30 m simulated street in 6
// frames, tiled into 6.4 m tiles, with the texture and semantic stages:
//  - a run SIGKILLed after its 1st, 3rd and last journaled tile (the test hook
//    VDBMAP_TEST_KILL_AFTER_TILES), then resumed, ends with the outputs of an uninterrupted run:
//    tiles.json, every tile file and map.vdb byte for byte (map.vdb: but for
//    OpenVDB's random file UUID), report.json but for timings, paths
//    and its "resume" section; the resumed run kept exactly the journaled tiles;
//  - a corrupted and a deleted tile file: exactly those two tiles are redone, with the reason;
//  - a changed semantic option or voxel size: every tile is redone, and the run says why;
//  - without --resume on an interrupted run's folder: the run says --resume exists and redoes all;
//  - a file-size limit (a full disk) during a tile: exit 1; a resume without it completes.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "pipeline/RunJournal.h"
#include "support/CliRun.h"
#include "support/OutputCompare.h"

namespace fs = std::filesystem;
using namespace vdbmap;
using Catch::Matchers::Contains;
using vdbmap::test::Child;
using vdbmap::test::ChildOptions;
using vdbmap::test::readText;

namespace {

fs::path workDir() { return fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "resume"; }

fs::path sequence() {
    const fs::path dir = workDir() / "seq";
    test::writeSimStreet(dir, 6, 30.0);
    return dir;
}

fs::path config() {
    const fs::path seq = sequence();  // creates workDir()
    const fs::path file = workDir() / ("tiled." + std::to_string(::getpid()) + ".yaml");
    std::ofstream out(file);
    out << "dataset: {format: kitti, path: " << seq.string() << ", max_range_m: 12}\n"
        << "plugins: [texture, semantic]\n"
        << "stages:\n"
        << "  - stage: integrate.atsdf\n    voxel_size_m: 0.2\n"
        << "  - stage: mesh.marching_cubes\n"
        << "  - stage: texture.mrf\n    max_view_angle_deg: 85\n"
        << "  - stage: semantic.mrf\n    max_view_angle_deg: 88\n"
        << "    lidar_labels: true\n    label_map: semantickitti\n"
        << "tiling: {tile_size_m: 6.4, halo_m: 1, occluder_margin_m: 3, max_view_distance_m: 20}\n";
    return file;
}

struct Run {
    int code = 0;
    std::string log;
};

Run run(const fs::path& out, std::vector<std::string> extra = {}, ChildOptions options = {}) {
    std::vector<std::string> args{"run", config().string(), "-o", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    Child child(test::kVdbmapExe, args, options);
    Run r;
    r.code = child.exitCode();
    r.log = child.log();
    return r;
}

ChildOptions killAfter(std::size_t tiles) {
    ChildOptions options;
    options.env = {{"VDBMAP_TEST_KILL_AFTER_TILES", std::to_string(tiles)}};
    return options;
}

/// The newest modification time of the programs a run uses (vdbmap, libvdbmap, the plugins),
/// so that a reference made by an earlier build is not reused after a rebuild.
std::string buildStamp() {
    fs::file_time_type newest = fs::last_write_time(test::kVdbmapExe);
    const fs::path lib = fs::path(VDBMAP_BINARY_DIR) / "lib";
    for (const auto& e : fs::recursive_directory_iterator(lib)) {
        if (e.is_regular_file()) newest = std::max(newest, e.last_write_time());
    }
    return std::to_string(newest.time_since_epoch().count());
}

/// An uninterrupted run, made once per build (written beside and renamed into place, as the
/// sequence).
fs::path reference() {
    const fs::path dir = workDir() / ("reference." + buildStamp());
    if (fs::exists(dir / "tiles.json")) return dir;
    const fs::path staging = workDir() / ("reference.writing." + std::to_string(::getpid()));
    fs::remove_all(staging);
    const Run r = run(staging);
    INFO(r.log);
    REQUIRE(r.code == 0);
    std::error_code ec;
    fs::rename(staging, dir, ec);
    if (ec) fs::remove_all(staging);
    return dir;
}

std::vector<nlohmann::json> journalLines(const fs::path& dir) {
    std::ifstream in(dir / "journal.jsonl");
    std::vector<nlohmann::json> lines;
    std::string line;
    while (std::getline(in, line)) lines.push_back(nlohmann::json::parse(line));
    return lines;
}

std::size_t journaledTiles(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& j : journalLines(dir)) n += j.contains("tile") ? 1 : 0;
    return n;
}

/// report.json without what may differ between two runs of the same inputs: times, memory,
/// paths and the resume section.
nlohmann::json comparableReport(const fs::path& dir) {
    nlohmann::json r = nlohmann::json::parse(readText(dir / "report.json"));
    r.erase("resume");
    r.erase("output_dir");
    r.erase("outputs");
    r["config"]["output"].erase("dir");
    r["config"].erase("overrides");
    r["config"].erase("source");
    std::function<void(nlohmann::json&)> strip = [&](nlohmann::json& j) {
        if (j.is_object()) {
            for (auto it = j.begin(); it != j.end();) {
                const std::string& key = it.key();
                // Times, rates and memory: "wall_time_s", "seconds", "ms_per_scan",
                // "faces_per_s_mrf", "timings_s", "peak_memory_bytes", "memory_estimate_bytes";
                // how the tiles ran side by side ("in_flight": tasks, waits).
                const bool timing = key == "timings" || key == "seconds" || key == "in_flight" ||
                                    key.rfind("ms_", 0) == 0 ||
                                    key.find("per_s") != std::string::npos ||
                                    key.find("memory") != std::string::npos ||
                                    (key.size() > 2 && key.compare(key.size() - 2, 2, "_s") == 0);
                if (timing) {
                    it = j.erase(it);
                } else {
                    strip(*it);
                    ++it;
                }
            }
        } else if (j.is_array()) {
            for (auto& e : j) strip(e);
        }
    };
    strip(r);
    return r;
}

/// A .vdb file's bytes without the random UUID OpenVDB writes into each file's header (bytes
/// 21..56: magic 8, file version 4, library version 8, offsets flag 1, UUID 36).
std::string withoutUuid(std::string bytes) {
    REQUIRE(bytes.size() > 57);
    bytes.replace(21, 36, 36, '-');
    return bytes;
}

/// The outputs of `dir` equal the reference's: tiles.json, every file below tiles/ and
/// map.vdb byte for byte (but for its UUID), report.json but for timings.
void requireSameOutputs(const fs::path& dir) {
    const fs::path ref = reference();
    CHECK(readText(dir / "tiles.json") == readText(ref / "tiles.json"));
    CHECK(withoutUuid(readText(dir / "map.vdb")) == withoutUuid(readText(ref / "map.vdb")));
    const auto a = test::filesBelow(ref / "tiles");
    const auto b = test::filesBelow(dir / "tiles");
    REQUIRE(a.size() > 10);
    CHECK(a.size() == b.size());
    for (const auto& [file, bytes] : a) {
        INFO(file);
        REQUIRE(b.count(file) == 1);
        CHECK(b.at(file) == bytes);
    }
    CHECK(comparableReport(dir).dump(1) == comparableReport(ref).dump(1));
}

nlohmann::json resumeSection(const fs::path& dir) {
    return nlohmann::json::parse(readText(dir / "report.json"))["resume"];
}

fs::path freshDir(const std::string& name) {
    const fs::path dir = workDir() / (name + "." + std::to_string(::getpid()));
    fs::remove_all(dir);
    return dir;
}

/// The name of the first tile of the reference's journal with a file below `subdir`.
std::string tileWith(const std::string& subdir, const std::string& skip = "") {
    for (const auto& j : journalLines(reference())) {
        if (!j.contains("tile") || j["tile"]["empty"].get<bool>()) continue;
        const std::string name = j["tile"]["name"];
        if (name == skip) continue;
        for (const auto& f : j["tile"]["files"]) {
            if (f["path"].get<std::string>().find("/" + subdir + "/") != std::string::npos)
                return name;
        }
    }
    return {};
}

}  // namespace

TEST_CASE("a run killed after its 1st, 3rd or last tile resumes to an uninterrupted run's outputs",
          "[resume][tiles][heavy]") {
    const fs::path ref = reference();
    const std::size_t total = journaledTiles(ref);
    REQUIRE(total >= 6);
    for (const std::size_t kill_after : {std::size_t(1), std::size_t(3), total}) {
        DYNAMIC_SECTION("killed after tile " << kill_after << " of " << total) {
            const fs::path dir = freshDir("killed" + std::to_string(kill_after));
            const Run killed = run(dir, {}, killAfter(kill_after));
            INFO(killed.log);
            REQUIRE(killed.code == -SIGKILL);
            CHECK(journaledTiles(dir) == kill_after);
            CHECK_FALSE(fs::exists(dir / "tiles.json"));

            const Run resumed = run(dir, {"--resume"});
            INFO(resumed.log);
            REQUIRE(resumed.code == 0);
            requireSameOutputs(dir);
            const nlohmann::json resume = resumeSection(dir);
            CHECK(resume["kept"] == kill_after);
            CHECK(resume["redone"] == 0);
            CHECK(resume["new"] == total - kill_after);
            // The journal now holds every tile once and the end of the run.
            CHECK(journaledTiles(dir) == total);
            CHECK(journalLines(dir).back().contains("end"));
        }
    }
}

TEST_CASE("a run killed while it writes map.vdb resumes with every tile kept", "[resume][tiles]") {
    const fs::path ref = reference();
    const std::size_t total = journaledTiles(ref);
    const fs::path dir = freshDir("killed_in_map_vdb");
    ChildOptions kill;
    kill.env = {{"VDBMAP_TEST_KILL_IN_MAP_VDB", "1"}};
    const Run killed = run(dir, {}, kill);
    INFO(killed.log);
    REQUIRE(killed.code == -SIGKILL);
    // Every tile was finished and journaled; map.vdb (atomic) and tiles.json were not written.
    CHECK(journaledTiles(dir) == total);
    CHECK_FALSE(fs::exists(dir / "map.vdb"));
    CHECK_FALSE(fs::exists(dir / "tiles.json"));

    const Run resumed = run(dir, {"--resume"});
    INFO(resumed.log);
    REQUIRE(resumed.code == 0);
    requireSameOutputs(dir);
    const nlohmann::json resume = resumeSection(dir);
    CHECK(resume["kept"] == total);
    CHECK(resume["redone"] == 0);
    CHECK(resume["new"] == 0);
}

TEST_CASE("a corrupted and a deleted tile file: exactly those two tiles are redone",
          "[resume][tiles]") {
    const fs::path ref = reference();
    const std::size_t total = journaledTiles(ref);
    const fs::path dir = freshDir("corrupt");
    fs::copy(ref, dir, fs::copy_options::recursive);
    const std::string corrupted = tileWith("semantic");
    const std::string deleted = tileWith("textured", corrupted);
    REQUIRE(!corrupted.empty());
    REQUIRE(!deleted.empty());
    {
        const fs::path mesh = dir / "tiles" / corrupted / "semantic" / "mesh.ply";
        std::fstream f(mesh, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(-1, std::ios::end);
        const char last = static_cast<char>(f.get());
        f.seekp(-1, std::ios::end);
        f.put(static_cast<char>(last ^ 0x01));  // same size, one bit flipped
    }
    fs::remove(dir / "tiles" / deleted / "textured" / "mesh.obj");

    const Run resumed = run(dir, {"--resume"});
    INFO(resumed.log);
    REQUIRE(resumed.code == 0);
    CHECK_THAT(resumed.log,
               Contains("tile " + corrupted + ": semantic/mesh.ply checksum differs, redoing"));
    CHECK_THAT(resumed.log,
               Contains("tile " + deleted + ": textured/mesh.obj is missing, redoing"));
    requireSameOutputs(dir);
    const nlohmann::json resume = resumeSection(dir);
    CHECK(resume["redone"] == 2);
    CHECK(resume["kept"] == total - 2);
    CHECK(resume["tiles"][corrupted]["reason"] == "semantic/mesh.ply checksum differs");
    CHECK(resume["tiles"][deleted]["action"] == "redone");
}

TEST_CASE("a changed semantic option or voxel size redoes every tile and says why",
          "[resume][tiles][heavy]") {
    const fs::path ref = reference();
    const std::size_t total = journaledTiles(ref);
    const fs::path dir = freshDir("changed");
    fs::copy(ref, dir, fs::copy_options::recursive);
    // Every tile runs semantic.mrf with this option: every tile's semantic outputs may change,
    // and the configuration is one of each tile's inputs, so all are redone.
    const Run changed = run(dir, {"--resume", "--set", "semantic.mrf.max_view_angle_deg=80"});
    INFO(changed.log);
    REQUIRE(changed.code == 0);
    CHECK_THAT(changed.log, Contains("max_view_angle_deg: 88.0 -> 80.0"));
    CHECK_THAT(changed.log, Contains("redoing every tile"));
    nlohmann::json resume = resumeSection(dir);
    CHECK(resume["kept"] == 0);
    CHECK(resume["redone"].get<std::size_t>() > 0);
    CHECK(resume["redone"].get<std::size_t>() + resume["new"].get<std::size_t>() >= total - 1);

    const Run voxel = run(dir, {"--resume", "--set", "semantic.mrf.max_view_angle_deg=80", "--set",
                                "integrate.atsdf.voxel_size_m=0.4"});
    INFO(voxel.log);
    REQUIRE(voxel.code == 0);
    CHECK_THAT(voxel.log, Contains("voxel_size_m changed (0.2 -> 0.4)"));
    resume = resumeSection(dir);
    CHECK(resume["kept"] == 0);
}

TEST_CASE("without --resume, a run on an interrupted run's folder says so and starts afresh",
          "[resume][tiles][heavy]") {
    const fs::path dir = freshDir("afresh");
    const Run killed = run(dir, {}, killAfter(2));
    REQUIRE(killed.code == -SIGKILL);
    const Run again = run(dir);
    INFO(again.log);
    REQUIRE(again.code == 0);
    CHECK_THAT(again.log, Contains("is the journal of an interrupted run (2 tiles finished); "
                                   "`vdbmap run --resume` would keep them; starting afresh"));
    CHECK(nlohmann::json::parse(readText(dir / "report.json")).count("resume") == 0);
    requireSameOutputs(dir);
    // A finished run's journal is not "interrupted".
    const Run third = run(dir);
    CHECK_THAT(third.log, !Contains("interrupted run"));
}

TEST_CASE("a full disk during a tile fails the run; a resume with space completes it",
          "[resume][tiles]") {
    const fs::path ref = reference();
    // The largest tile file: a limit just below it fails the run while that tile is written,
    // after the tiles before it were journaled.
    std::uintmax_t largest = 0;
    for (const auto& e : fs::recursive_directory_iterator(ref / "tiles")) {
        if (e.is_regular_file()) largest = std::max(largest, e.file_size());
    }
    const fs::path dir = freshDir("full");
    ChildOptions limited;
    limited.file_size_limit = largest - 1;
    const Run full = run(dir, {}, limited);
    INFO(full.log);
    REQUIRE(full.code == 1);
    CHECK_FALSE(fs::exists(dir / "tiles.json"));
    const Run resumed = run(dir, {"--resume"});
    INFO(resumed.log);
    REQUIRE(resumed.code == 0);
    requireSameOutputs(dir);
}

TEST_CASE("the journal's checksum, config differences and a torn last line", "[resume]") {
    // FNV-1a 64 reference values (Fowler, Noll, Vo: the test vectors of the FNV page).
    CHECK(detail::hex64(detail::fnv1a64("")) == "cbf29ce484222325");
    CHECK(detail::hex64(detail::fnv1a64("a")) == "af63dc4c8601ec8c");
    CHECK(detail::hex64(detail::fnv1a64("foobar")) == "85944171f73967e8");
    // Continued hashing equals hashing the concatenation (files are hashed in blocks).
    CHECK(detail::fnv1a64("bar", detail::fnv1a64("foo")) == detail::fnv1a64("foobar"));

    const nlohmann::json before = {
        {"stages", {{{"stage", "semantic.mrf"}, {"options", {{"x", 1.0}}}}}}};
    nlohmann::json now = before;
    now["stages"][0]["options"]["x"] = 2.0;
    const auto diffs = detail::configDifferences(before, now);
    REQUIRE(diffs.size() == 1);
    CHECK(diffs[0] == "stages[0] semantic.mrf x: 1.0 -> 2.0");

    // A journal whose last line a kill cut in half: the line is skipped, the rest is read.
    const fs::path dir = freshDir("torn");
    fs::create_directories(dir);
    const auto header =
        detail::JournalHeader::fromResolvedConfig(R"({"output": {"dir": "x"}, "stages": []})");
    detail::RunJournal::start(dir, header, {});
    {
        detail::RunJournal journal(dir);
        detail::TileOutcome empty;
        empty.name = "0_0";
        journal.append(detail::tileEntry({{"config", header.config_hash}}, empty, dir));
    }
    std::ofstream(dir / "journal.jsonl", std::ios::app) << R"({"tile": {"name": "1_0", "inp)";
    const auto contents = detail::RunJournal::read(dir);
    REQUIRE(contents);
    REQUIRE(contents->header);
    CHECK(contents->header->config_hash == header.config_hash);
    CHECK(contents->tiles.size() == 1);
    CHECK(contents->tiles.count("0_0") == 1);
    CHECK(contents->bad_lines == 1);
    CHECK_FALSE(contents->finished);
    // output.dir is not part of what decides a tile.
    CHECK(detail::JournalHeader::fromResolvedConfig(R"({"output": {"dir": "y"}, "stages": []})")
              .config_hash == header.config_hash);
}
