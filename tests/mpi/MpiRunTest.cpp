// SPDX-License-Identifier: Apache-2.0
// vdbmap-mpi under `mpirun --oversubscribe -np 3` (issue 13): the same tiles, index and map as
// the single-process tiled run; each rank reads a stretch of the scans; a failing rank fails
// the job with exit 1 naming the tile, and no tiles.json is written; more ranks than tiles
// is a warning; a tile worked in pieces (a budget below its estimate) gives the single-process
// run's pieces. OMPI_ALLOW_RUN_AS_ROOT(_CONFIRM) are set for the mpirun child only.
#include <catch2/catch.hpp>

#include <signal.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "support/CliRun.h"
#include "support/OutputCompare.h"
#include "vdbmap/dynamic/DynamicPoints.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;
using namespace vdbmap;
using vdbmap::test::Child;
using vdbmap::test::ChildOptions;
using vdbmap::test::filesBelow;
using vdbmap::test::readText;
using vdbmap::test::vdbVoxels;

namespace {

const fs::path kMpiExe = fs::path(VDBMAP_BINARY_DIR) / "bin" / "vdbmap-mpi";

fs::path workDir() { return fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "mpi_run"; }

/// A 60 m street in 12 frames (images, semantic images, LiDAR labels), written once.
fs::path sequence() {
    const fs::path dir = workDir() / "seq";
    test::writeSimStreet(dir, 12, 60.0);
    return dir;
}

/// The same street with traffic (cars, a van, pedestrians in the LiDAR and the images),
/// written once; only one test case uses it.
fs::path trafficSequence() {
    const fs::path dir = workDir() / "seq_traffic";
    if (fs::exists(dir / "gt" / "sim.json")) return dir;
    fs::create_directories(workDir());
    const fs::path staging = workDir() / ("seq_traffic.writing." + std::to_string(::getpid()));
    fs::remove_all(staging);
    SimOptions sim;
    sim.frames = 12;
    sim.size_m = 60.0;
    sim.gt_views = 0;
    sim.traffic = 3;
    sim.quiet = true;
    writeSimSequence(sim, staging);
    fs::rename(staging, dir);
    return dir;
}

/// A tiled pipeline over `seq` with a 12 m range filter (each rank needs a stretch of the
/// scans), written to `file`. `atsdf_options`: more lines of the integrate.atsdf stage.
fs::path writeConfig(const fs::path& file, const fs::path& seq, double tile_size_m,
                     const std::string& atsdf_options = "", const std::string& tiling_extra = "") {
    std::ofstream out(file);
    out << "dataset: {format: kitti, path: " << seq.string() << ", max_range_m: 12}\n"
        << "plugins: [texture, semantic]\n"
        << "stages:\n"
        << "  - stage: integrate.atsdf\n    voxel_size_m: 0.2\n" << atsdf_options
        << "  - stage: mesh.marching_cubes\n"
        << "  - stage: texture.mrf\n    max_view_angle_deg: 85\n"
        << "  - stage: semantic.mrf\n    max_view_angle_deg: 88\n"
        << "    lidar_labels: true\n    label_map: semantickitti\n"
        << "tiling: {tile_size_m: " << tile_size_m
        << ", halo_m: 1, occluder_margin_m: 3, max_view_distance_m: 20" << tiling_extra << "}\n";
    return file;
}

ChildOptions mpiEnv() {
    ChildOptions options;
    options.env = {{"OMPI_ALLOW_RUN_AS_ROOT", "1"}, {"OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1"}};
    // Under the sanitizer build (scripts/sanitize.sh): no leak detection in mpirun and its
    // ranks. Open MPI 4.1's runtime (opal, hwloc, the mca components it dlopens and closes at
    // MPI_Finalize) keeps allocations for the life of every rank, and their stacks end in
    // unloaded components, so no suppression can name them. ASan's memory errors and UBSan
    // stay on; our code's leaks are checked by the single-process runs of the same tiled
    // pipeline (this file's `vdbmap run` children, TiledPipelineTest). A later ASan option
    // overrides an earlier one.
    if (const char* asan = std::getenv("ASAN_OPTIONS")) {
        options.env.emplace_back("ASAN_OPTIONS", std::string(asan) + ":detect_leaks=0");
    }
    return options;
}

/// `vdbmap run config -o out --quiet` in one process; it must succeed.
void runSingle(const fs::path& config, const fs::path& out) {
    Child one(test::kVdbmapExe, {"run", config.string(), "-o", out.string(), "--quiet"});
    const int code = one.exitCode();
    INFO(one.log());
    REQUIRE(code == 0);
}

/// Checks that the files below a/tiles and b/tiles are the same, byte for byte; returns how
/// many of them lie in a piece's folder (`<ix>_<iy>.<piece>/`).
std::size_t samePieceFiles(const fs::path& a_dir, const fs::path& b_dir) {
    const auto a = filesBelow(a_dir / "tiles");
    const auto b = filesBelow(b_dir / "tiles");
    std::size_t piece_files = 0;
    CHECK(a.size() == b.size());
    for (const auto& [file, bytes] : a) {
        INFO(file);
        REQUIRE(b.count(file) == 1);
        CHECK(b.at(file) == bytes);
        piece_files += file.substr(0, file.find('/')).find('.') != std::string::npos ? 1 : 0;
    }
    return piece_files;
}

std::vector<std::string> mpiArgs(int ranks, const fs::path& config, const fs::path& out) {
    return {"--oversubscribe", "-np", std::to_string(ranks), kMpiExe.string(), "run",
            config.string(), "-o", out.string(), "--quiet"};
}

}  // namespace

TEST_CASE("mpirun -np 3 writes the tiles, index and map of the single-process run", "[mpi][tiles]") {
    // With traffic, and moving points found by the free-space test alone (not the labels):
    // each scan's moving points are decided by one rank for all (issue 37), and every rank
    // must drop the points the single process drops.
    const fs::path seq = trafficSequence();
    const fs::path config = writeConfig(workDir() / "tiled.yaml", seq, 12.8,
                                        "    dynamic_use_labels: false\n");
    const fs::path single = workDir() / "single", mpi = workDir() / "mpi3";
    fs::remove_all(single);
    fs::remove_all(mpi);
    runSingle(config, single);
    Child three(VDBMAP_MPIEXEC, mpiArgs(3, config, mpi), mpiEnv());
    INFO(three.log());
    REQUIRE(three.exitCode() == 0);

    // Meshes, labels, textures and the index: byte for byte.
    const auto a = filesBelow(single / "tiles");
    const auto b = filesBelow(mpi / "tiles");
    REQUIRE(a.size() > 20);
    CHECK(a.size() == b.size());
    for (const auto& [file, bytes] : a) {
        INFO(file);
        REQUIRE(b.count(file) == 1);
        CHECK(b.at(file) == bytes);
    }
    CHECK(readText(single / "tiles.json") == readText(mpi / "tiles.json"));
    // map.vdb: rank 0 gathered every rank's own leaves into one file of the whole map.
    CHECK(vdbVoxels(single / "map.vdb") == vdbVoxels(mpi / "map.vdb"));

    const nlohmann::json report = nlohmann::json::parse(readText(mpi / "report.json"));
    const nlohmann::json index = nlohmann::json::parse(readText(mpi / "tiles.json"));
    CHECK(report["status"]["state"] == "done");
    CHECK(report["distributed"]["processes"] == 3);
    REQUIRE(report["distributed"]["process"].size() == 3);
    std::size_t tiles = 0, partial = 0;
    const std::size_t frames = report["counts"]["frames"];
    for (const auto& p : report["distributed"]["process"]) {
        tiles += p["tiles"].get<std::size_t>();
        CHECK(p["tiles"].get<std::size_t>() > 0);
        // Each rank integrated only the scans its tiles need: a stretch of the drive (the
        // middle rank's stretch may be all of this short one).
        CHECK(p["frames_integrated"].get<std::size_t>() > 0);
        CHECK(p["frames_integrated"].get<std::size_t>() <= frames);
        partial += p["frames_integrated"].get<std::size_t>() < frames ? 1 : 0;
    }
    CHECK(partial >= 2);
    CHECK(tiles == index["tiles"].size());
    CHECK(report["tiles"].size() == index["tiles"].size());

    // The moving points: the same ones (rank 0 merges the ranks' parts), and some there are.
    const DynamicPoints moving_one = readDynamicPointsPly(single / "dynamic_points.ply");
    const DynamicPoints moving_mpi = readDynamicPointsPly(mpi / "dynamic_points.ply");
    CHECK(moving_one.size() > 100);
    CHECK(moving_mpi.frame == moving_one.frame);
    CHECK(moving_mpi.index == moving_one.index);
    // Rank 0 tested some of its scans for every rank and took the others' decisions for the
    // rest: every scan it integrated was decided once, here or elsewhere.
    const nlohmann::json& dyn = report["stages"]["integrate.atsdf"]["dynamic_removal"];
    const std::size_t frames0 = report["distributed"]["process"][0]["frames_integrated"];
    CHECK(dyn["scans_decided_for_all"].get<std::size_t>() > 0);
    CHECK(dyn["scans_decided_for_all"].get<std::size_t>() < frames);
    CHECK(dyn["scans_adopted"].get<std::size_t>() > 0);
    CHECK(dyn["scans_adopted"].get<std::size_t>() <= frames0);
}

TEST_CASE("map_vdb: per_tile under mpirun -np 3: each rank writes its tiles' map.vdb, nothing gathered",
          "[mpi][tiles][map]") {
    // Each rank drops the leaves none of its tiles still reads, and writes its tiles' own
    // map.vdb: the single-process run's, grid for grid.
    const fs::path seq = sequence();
    const fs::path config =
        writeConfig(workDir() / "per_tile.yaml", seq, 12.8, "", ", map_vdb: per_tile");
    const fs::path single = workDir() / "per_tile_single", mpi = workDir() / "per_tile_mpi3";
    fs::remove_all(single);
    fs::remove_all(mpi);
    runSingle(config, single);
    Child three(VDBMAP_MPIEXEC, mpiArgs(3, config, mpi), mpiEnv());
    INFO(three.log());
    REQUIRE(three.exitCode() == 0);

    const auto a = filesBelow(single / "tiles");
    const auto b = filesBelow(mpi / "tiles");
    CHECK(a.size() == b.size());
    std::size_t maps = 0;
    for (const auto& [file, bytes] : a) {
        INFO(file);
        REQUIRE(b.count(file) == 1);
        if (fs::path(file).filename() == "map.vdb") {  // a .vdb file holds a random UUID
            CHECK(vdbVoxels(single / "tiles" / file) == vdbVoxels(mpi / "tiles" / file));
            ++maps;
        } else {
            CHECK(b.at(file) == bytes);
        }
    }
    const nlohmann::json index = nlohmann::json::parse(readText(mpi / "tiles.json"));
    CHECK(maps == index["tiles"].size());
    CHECK(maps > 3);
    CHECK(readText(single / "tiles.json") == readText(mpi / "tiles.json"));
    CHECK_FALSE(fs::exists(mpi / "map.vdb"));
    CHECK_FALSE(fs::exists(single / "map.vdb"));
    const nlohmann::json report = nlohmann::json::parse(readText(mpi / "report.json"));
    const nlohmann::json report_one = nlohmann::json::parse(readText(single / "report.json"));
    CHECK(report["counts"]["active_voxels"] == report_one["counts"]["active_voxels"]);
    CHECK(report_one["counts"]["active_voxels"].get<std::size_t>() > 0);
}

TEST_CASE("A tile worked in pieces under mpirun -np 2: the single-process run's pieces, byte for byte",
          "[mpi][tiles][split][heavy]") {
    // The largest tile's estimate from a run with a budget above every tile, then a budget
    // just below it (the same on every rank: the split depends on the tile and the budget).
    const fs::path seq = sequence();
    const fs::path whole = workDir() / "split_whole", single = workDir() / "split_single",
                   mpi = workDir() / "split_mpi2";
    for (const fs::path& p : {whole, single, mpi}) fs::remove_all(p);
    Child first(test::kVdbmapExe, {"run", writeConfig(workDir() / "split_whole.yaml", seq, 12.8, "",
                                                      ", memory_budget_gb: 64").string(),
                                   "-o", whole.string(), "--quiet"});
    const int first_code = first.exitCode();
    INFO(first.log());
    REQUIRE(first_code == 0);
    std::size_t largest = 0;
    const nlohmann::json whole_report = nlohmann::json::parse(readText(whole / "report.json"));
    for (const auto& [name, tile] : whole_report["tiles"].items()) {
        largest = std::max(largest, tile["memory_estimate_bytes"].get<std::size_t>());
    }
    REQUIRE(largest > (64u << 20) + (512u << 10));  // the budget above the estimate's fixed part
    char budget[64];
    std::snprintf(budget, sizeof(budget), ", memory_budget_gb: %.9f",
                  static_cast<double>(largest - (512u << 10)) / (1024.0 * 1024.0 * 1024.0));
    const fs::path config = writeConfig(workDir() / "split.yaml", seq, 12.8, "", budget);
    runSingle(config, single);
    Child two(VDBMAP_MPIEXEC, mpiArgs(2, config, mpi), mpiEnv());
    INFO(two.log());
    REQUIRE(two.exitCode() == 0);

    const nlohmann::json report = nlohmann::json::parse(readText(mpi / "report.json"));
    CHECK(report["tiling"]["split_tiles"].get<std::size_t>() >= 1);
    CHECK(report["tiling"]["split_tiles"] ==
          nlohmann::json::parse(readText(single / "report.json"))["tiling"]["split_tiles"]);
    CHECK(samePieceFiles(single, mpi) > 0);
    CHECK(readText(single / "tiles.json") == readText(mpi / "tiles.json"));
    CHECK(vdbVoxels(single / "map.vdb") == vdbVoxels(mpi / "map.vdb"));
}

TEST_CASE("A failing rank fails the job with exit 1, names the tile, writes no tiles.json",
          "[mpi][tiles]") {
    // A copy of the sequence with one unreadable semantic image in the middle of the drive:
    // only the tiles that view sees fail, on whichever rank has them.
    const fs::path seq = sequence();
    const fs::path broken = workDir() / "seq_broken";
    if (!fs::exists(broken)) fs::copy(seq, broken, fs::copy_options::recursive);
    const fs::path bad_image = broken / "semantic_2" / "000006.png";
    REQUIRE(fs::exists(bad_image));
    std::ofstream(bad_image, std::ios::trunc) << "not a png";
    const fs::path config = writeConfig(workDir() / "broken.yaml", broken, 12.8);
    const fs::path out = workDir() / "mpi_broken";
    fs::remove_all(out);
    fs::create_directories(out);
    std::ofstream(out / "tiles.json") << "{\"stale\": true}";  // an earlier run's index

    Child job(VDBMAP_MPIEXEC, mpiArgs(3, config, out), mpiEnv());
    const int code = job.exitCode();
    const std::string log = job.log();
    INFO(log);
    CHECK(code == 1);
    // vdbmap-mpi prints "tile <ix>_<iy>: semantic.mrf: ...<file>..." once (rank 0).
    const auto at = log.find("tile ");
    REQUIRE(at != std::string::npos);
    CHECK(log.find("semantic.mrf", at) != std::string::npos);
    CHECK(log.find("000006.png", at) != std::string::npos);
    CHECK_FALSE(fs::exists(out / "tiles.json"));
    const nlohmann::json report = nlohmann::json::parse(readText(out / "report.json"));
    CHECK(report["status"]["state"] == "failed");
    CHECK(report["status"]["exit_code"] == 1);
    CHECK(report["status"]["error"].get<std::string>().rfind("tile ", 0) == 0);
}

TEST_CASE("mpirun with more ranks than tiles warns and still writes every tile", "[mpi][tiles][heavy]") {
    const fs::path seq = sequence();
    // 64 m tiles: the 60 m street and its reach touch at most 6 tiles.
    const fs::path config = writeConfig(workDir() / "big_tiles.yaml", seq, 64.0);
    const fs::path single = workDir() / "big_single", mpi = workDir() / "big_mpi";
    fs::remove_all(single);
    fs::remove_all(mpi);
    runSingle(config, single);
    // At most 6 tiles within reach (4 written: the street crosses x = 0 and z = 0).
    Child job(VDBMAP_MPIEXEC, mpiArgs(7, config, mpi), mpiEnv());
    const int code = job.exitCode();
    INFO(job.log());
    CHECK(code == 0);
    CHECK(job.log().find("7 processes but only") != std::string::npos);
    CHECK(job.log().find("process(es) get no tile") != std::string::npos);
    CHECK(job.log().find("tiling.split_for_processes: 7") != std::string::npos);  // the way out
    CHECK(readText(single / "tiles.json") == readText(mpi / "tiles.json"));
    CHECK(filesBelow(single / "tiles") == filesBelow(mpi / "tiles"));
}

TEST_CASE("split_for_processes: 7 cuts the few tiles into pieces for 7 ranks, as in one process",
          "[mpi][tiles][split][heavy]") {
    // Issue 37, ranks that outnumber the tiles: the plan cuts the costliest tiles into pieces
    // until every rank has work. The pieces depend on the setting, not on the ranks: the
    // single-process run with the same setting writes the same files.
    const fs::path seq = sequence();
    const fs::path config =
        writeConfig(workDir() / "balance.yaml", seq, 64.0, "", ", split_for_processes: 7");
    const fs::path single = workDir() / "balance_single", mpi = workDir() / "balance_mpi";
    fs::remove_all(single);
    fs::remove_all(mpi);
    runSingle(config, single);
    Child job(VDBMAP_MPIEXEC, mpiArgs(7, config, mpi), mpiEnv());
    const int code = job.exitCode();
    INFO(job.log());
    REQUIRE(code == 0);
    CHECK(job.log().find("get no tile") == std::string::npos);

    const nlohmann::json report = nlohmann::json::parse(readText(mpi / "report.json"));
    REQUIRE(report["distributed"]["process"].size() == 7);
    // Every rank was given pieces to work (on this small street many hold no observed leaf,
    // and the estimates are at their floor: docs/benchmarks/scale.md measures the balance).
    std::size_t planned_pieces = 0;
    std::set<int> ranks;
    for (const auto& t : report["tiling"]["plan"]) {
        planned_pieces += t["name"].get<std::string>().find('.') != std::string::npos ? 1 : 0;
        ranks.insert(t["process"].get<int>());
    }
    CHECK(planned_pieces >= 7);
    CHECK(planned_pieces == report["tiling"]["balance_pieces"].get<std::size_t>());
    CHECK(ranks.size() == 7);

    CHECK(samePieceFiles(single, mpi) > 0);
    CHECK(readText(single / "tiles.json") == readText(mpi / "tiles.json"));
    // map.vdb: the leaves of a cut tile come from its first piece's rank, which integrated the
    // whole tile's region.
    CHECK(vdbVoxels(single / "map.vdb") == vdbVoxels(mpi / "map.vdb"));
    // The pieces cover what the whole tiles did: the same faces over all tiles.
    const fs::path whole = workDir() / "balance_whole";
    fs::remove_all(whole);
    runSingle(writeConfig(workDir() / "balance_whole.yaml", seq, 64.0), whole);
    auto faces = [](const fs::path& index) {
        std::size_t n = 0;
        for (const auto& t : nlohmann::json::parse(readText(index))["tiles"]) {
            n += t["counts"]["faces"].get<std::size_t>();
        }
        return n;
    };
    CHECK(faces(single / "tiles.json") == faces(whole / "tiles.json"));
    CHECK(nlohmann::json::parse(readText(single / "tiles.json"))["tiles"].size() >
          nlohmann::json::parse(readText(whole / "tiles.json"))["tiles"].size());
}

TEST_CASE("mpirun -np 2 vdbmap run stops at once, naming vdbmap-mpi run", "[mpi]") {
    const fs::path seq = sequence();
    const fs::path config = writeConfig(workDir() / "plain.yaml", seq, 12.8);
    const fs::path out = workDir() / "vdbmap_under_mpirun";
    fs::remove_all(out);
    Child two(VDBMAP_MPIEXEC,
              {"--oversubscribe", "-np", "2", test::kVdbmapExe.string(), "run", config.string(),
               "-o", out.string(), "--quiet"},
              mpiEnv());
    const int code = two.exitCode();
    INFO(two.log());
    CHECK(code == 2);
    CHECK(two.log().find("vdbmap-mpi run") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("A single-process run killed is resumed under mpirun -np 3, and the other way round",
          "[mpi][tiles][resume][heavy]") {
    // docs/tiling.md "Resume": the journal's tiles are kept whichever process count wrote or
    // reads it; the outputs are those of an uninterrupted single-process run.
    const fs::path seq = sequence();
    const fs::path config = writeConfig(workDir() / "resume.yaml", seq, 12.8);
    const fs::path ref = workDir() / "resume_ref";
    fs::remove_all(ref);
    Child reference(test::kVdbmapExe, {"run", config.string(), "-o", ref.string(), "--quiet"});
    REQUIRE(reference.exitCode() == 0);
    auto requireSame = [&](const fs::path& out) {
        const auto a = filesBelow(ref / "tiles");
        const auto b = filesBelow(out / "tiles");
        CHECK(a.size() == b.size());
        for (const auto& [file, bytes] : a) {
            INFO(file);
            REQUIRE(b.count(file) == 1);
            CHECK(b.at(file) == bytes);
        }
        CHECK(readText(ref / "tiles.json") == readText(out / "tiles.json"));
        CHECK(vdbVoxels(ref / "map.vdb") == vdbVoxels(out / "map.vdb"));
    };
    auto kept = [](const fs::path& out) {
        return nlohmann::json::parse(readText(out / "report.json"))["resume"]["kept"].get<int>();
    };

    SECTION("killed single-process run, resumed by 3 ranks") {
        const fs::path out = workDir() / "resume_to_mpi";
        fs::remove_all(out);
        ChildOptions kill;
        kill.env = {{"VDBMAP_TEST_KILL_AFTER_TILES", "2"}};
        Child killed(test::kVdbmapExe, {"run", config.string(), "-o", out.string(), "--quiet"}, kill);
        REQUIRE(killed.exitCode() == -SIGKILL);
        std::vector<std::string> args = mpiArgs(3, config, out);
        args.push_back("--resume");
        Child job(VDBMAP_MPIEXEC, args, mpiEnv());
        INFO(job.log());
        REQUIRE(job.exitCode() == 0);
        requireSame(out);
        CHECK(kept(out) == 2);
    }
    SECTION("killed 3-rank run, resumed by one process") {
        const fs::path out = workDir() / "resume_from_mpi";
        fs::remove_all(out);
        ChildOptions env = mpiEnv();
        env.env.emplace_back("VDBMAP_TEST_KILL_AFTER_TILES", "1");
        std::vector<std::string> args = mpiArgs(3, config, out);
        args.insert(args.begin(), {"-x", "VDBMAP_TEST_KILL_AFTER_TILES"});
        Child job(VDBMAP_MPIEXEC, args, env);
        CHECK(job.exitCode() != 0);
        CHECK_FALSE(fs::exists(out / "tiles.json"));
        Child resumed(test::kVdbmapExe,
                      {"run", config.string(), "-o", out.string(), "--quiet", "--resume"});
        INFO(resumed.log());
        REQUIRE(resumed.exitCode() == 0);
        requireSame(out);
        CHECK(kept(out) >= 1);
    }
}
