// SPDX-License-Identifier: Apache-2.0
// A map.vdb per tile (tiling.map_vdb: per_tile, issue 37): each tile writes the leaves of its
// core, as the whole run's map.vdb holds them; the tiles' files are those of a run that keeps
// the whole map; and the leaves no tile still to come reads leave memory. VoxelMap's filtered
// grids and dropLeaves against the slow per-voxel reading of the same map.
#include <catch2/catch.hpp>

#include <openvdb/io/File.h>

#include <array>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "support/OutputCompare.h"
#include "support/PluginPath.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/map/BlockStats.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;
using namespace vdbmap;
using vdbmap::test::filesBelow;
using vdbmap::test::readText;
using vdbmap::test::vdbVoxels;

namespace {

using Voxels = std::map<std::array<int, 3>, float>;

/// A map of three leaves along x (origins 0, 8, 16), two voxels each, the first moved to the
/// compact store, with block statistics for each and a fourth statistics-only block.
void fillMap(VoxelMap& map) {
    for (int leaf = 0; leaf < 3; ++leaf) {
        map.setVoxel(openvdb::Coord(8 * leaf + 1, 2, 3), 0.01f * static_cast<float>(leaf + 1), 2.0f);
        map.setVoxel(openvdb::Coord(8 * leaf + 5, 6, 7), -0.02f, 3.0f + static_cast<float>(leaf));
        map.blockStats().entry(map.blockStats().findOrCreate(openvdb::Coord(leaf, 0, 0))).truncation_m =
            0.1f * static_cast<float>(leaf + 1);
        if (leaf == 0) map.compact();
    }
    map.blockStats().findOrCreate(openvdb::Coord(9, 9, 9));
}

Voxels gridVoxels(const openvdb::FloatGrid& grid) {
    Voxels out;
    for (auto it = grid.cbeginValueOn(); it; ++it) out[{it.getCoord().x(), it.getCoord().y(), it.getCoord().z()}] = *it;
    return out;
}

/// The slow reference: every voxel probed one by one, kept when its leaf passes `keep`.
Voxels probedSurface(const VoxelMap& map, const VoxelMap::LeafFilter& keep) {
    Voxels out;
    for (int x = -8; x < 32; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z) {
                float sdf = 0.0f, weight = 0.0f;
                const openvdb::Coord c(x, y, z);
                if (map.probeVoxel(c, sdf, weight) && keep(c & ~7)) out[{x, y, z}] = sdf;
            }
    return out;
}

}  // namespace

TEST_CASE("VoxelMap: grids of a part of the map, and leaves dropped from both stores", "[map][tiles]") {
    VoxelMap map(0.1);
    fillMap(map);
    REQUIRE(map.leafCount() == 3);
    REQUIRE(map.workingLeafCount() == 2);
    const auto not_middle = [](const openvdb::Coord& o) { return o.x() != 8; };

    // The filtered surface grid holds the voxels the probe finds in the kept leaves.
    const Voxels part = gridVoxels(*map.surfaceGrid(not_middle));
    CHECK(part == probedSurface(map, not_middle));
    CHECK(part.size() == 4);
    CHECK(gridVoxels(*map.surfaceGrid()).size() == 6);
    const Voxels eps = gridVoxels(*map.truncationGrid(9.0f, not_middle));
    CHECK(eps.at({1, 2, 3}) == Approx(0.1f));
    CHECK(eps.at({21, 6, 7}) == Approx(0.3f));

    // Dropping the middle leaf (working) and the first (compact) leaves the third as it was,
    // its block statistics found at their new index.
    const auto third = [](const openvdb::Coord& o) { return o.x() == 16; };
    const Voxels before = probedSurface(map, third);
    CHECK(map.dropLeaves([&](const openvdb::Coord& o) { return !third(o) && o.x() < 24; }) == 2);
    CHECK(map.leafCount() == 1);
    CHECK(map.activeVoxelCount() == 2);
    CHECK(probedSurface(map, [](const openvdb::Coord&) { return true; }) == before);
    CHECK(map.blockStats().find(openvdb::Coord(0, 0, 0)) == -1);
    CHECK(map.blockStats().find(openvdb::Coord(1, 0, 0)) == -1);
    const std::int32_t kept = map.blockStats().find(openvdb::Coord(2, 0, 0));
    REQUIRE(kept >= 0);
    CHECK(map.blockStats().entry(kept).truncation_m == Approx(0.3f));
    CHECK(map.blockStats().blockCoord(kept) == openvdb::Coord(2, 0, 0));
    const std::int32_t lone = map.blockStats().find(openvdb::Coord(9, 9, 9));  // no TSDF leaf, kept
    REQUIRE(lone >= 0);
    CHECK(map.blockStats().blockCoord(lone) == openvdb::Coord(9, 9, 9));
    CHECK(map.blockStats().size() == 2);
    // A dropped leaf can come back (a later scan there): it starts unobserved.
    map.setVoxel(openvdb::Coord(9, 2, 3), 0.05f, 1.0f);
    CHECK(map.activeVoxelCount() == 3);
    CHECK(map.dropLeaves(nullptr) == 0);
}

namespace {

/// 40 m of street in 8 frames, 6.4 m tiles at 0.2 m (32 voxels): most tiles are finished
/// while the scans come in, with texture and semantics on each.
std::string yaml(const std::string& tiling_extra) {
    return "dataset: {format: kitti, path: seq, min_range_m: 1.0, max_range_m: 20}\n"
           "plugins: [\"" + test::builtPluginPath("texture") + "\", \"" +
           test::builtPluginPath("semantic") + "\"]\n"
           "stages:\n"
           "  - stage: integrate.atsdf\n"
           "    voxel_size_m: 0.2\n"
           "  - stage: mesh.marching_cubes\n"
           "  - stage: semantic.mrf\n"
           "    max_view_angle_deg: 88\n"
           "  - stage: texture.mrf\n"
           "    max_view_angle_deg: 85\n"
           "tiling: {tile_size_m: 6.4, halo_m: 1, occluder_margin_m: 3, max_view_distance_m: 20" +
           tiling_extra + "}\n";
}

fs::path streetRoot() {
    setLogLevel(LogLevel::Warn);
    const fs::path r = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "tile_map_vdb";
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

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

TEST_CASE("A map.vdb per tile holds the whole map's leaves of its core; the tiles stay the same",
          "[tiles][pipeline][map][heavy]") {
    const fs::path root = streetRoot();
    const nlohmann::json whole = run(root, "whole", ", max_tiles_in_flight: 2, memory_budget_gb: 64");
    const nlohmann::json per_tile =
        run(root, "per_tile", ", max_tiles_in_flight: 2, memory_budget_gb: 64, map_vdb: per_tile");
    // One tile after the other, every tile after the last scan: nothing dropped while
    // integrating, the map finalized before any tile.
    const nlohmann::json late = run(root, "late", ", max_tiles_in_flight: 1, stream: false, map_vdb: per_tile");

    CHECK_FALSE(fs::exists(root / "per_tile" / "map.vdb"));
    REQUIRE(fs::exists(root / "whole" / "map.vdb"));
    const nlohmann::json index = nlohmann::json::parse(readText(root / "per_tile" / "tiles.json"));
    REQUIRE(index["tiles"].size() > 10);

    // Every file of the whole-map run's tiles, byte for byte, and one map.vdb more per tile.
    const auto expected = filesBelow(root / "whole" / "tiles");
    const auto files = filesBelow(root / "per_tile" / "tiles");
    CHECK(files.size() == expected.size() + index["tiles"].size());
    for (const auto& [file, bytes] : expected) {
        INFO(file);
        REQUIRE(files.count(file) == 1);
        CHECK(files.at(file) == bytes);
    }
    // Any order of finishing: the same per-tile files, the same index. (A .vdb file holds a
    // random UUID: its grids are compared.)
    const auto late_files = filesBelow(root / "late" / "tiles");
    CHECK(late_files.size() == files.size());
    for (const auto& [file, bytes] : files) {
        INFO(file);
        REQUIRE(late_files.count(file) == 1);
        if (fs::path(file).filename() == "map.vdb") {
            CHECK(vdbVoxels(root / "late" / "tiles" / file) == vdbVoxels(root / "per_tile" / "tiles" / file));
        } else {
            CHECK(late_files.at(file) == bytes);
        }
    }
    CHECK(readText(root / "late" / "tiles.json") == readText(root / "per_tile" / "tiles.json"));

    // The tiles' grids put together are the whole map's voxels in the cores of those tiles.
    const int tile_vox = 32;
    const std::string up = index["up_axis"];
    const int up_axis = up == "x" ? 0 : up == "y" ? 1 : 2;
    const int ax0 = up_axis == 0 ? 1 : 0, ax1 = up_axis == 2 ? 1 : 2;
    std::map<std::string, Voxels> joined;
    std::set<std::pair<int, int>> cells;
    std::size_t map_voxels = 0;
    for (const auto& tile : index["tiles"]) {
        const std::string name = tile["name"];
        INFO(name);
        const fs::path file = root / "per_tile" / "tiles" / name / "map.vdb";
        REQUIRE(fs::exists(file));
        const std::string rel = "tiles/" + name + "/map.vdb";
        const auto& listed = tile["files"];
        CHECK(std::find(listed.begin(), listed.end(), rel) != listed.end());
        const int ix = tile["ix"], iy = tile["iy"];
        cells.insert({ix, iy});
        for (const auto& [grid, voxels] : vdbVoxels(file)) {
            for (const auto& [c, v] : voxels) {
                CHECK(floorDiv(c[ax0], tile_vox) == ix);
                CHECK(floorDiv(c[ax1], tile_vox) == iy);
                CHECK(joined[grid].emplace(c, v).second);  // in one tile only
            }
        }
        map_voxels += tile["counts"]["map_voxels"].get<std::size_t>();
        // The file names its tile and the map's settings; the run's scan count is not its own.
        openvdb::io::File f(file.string());
        f.open();
        const openvdb::MetaMap::Ptr meta = f.getMetadata();
        CHECK(meta->metaValue<std::string>("tile") == name);
        CHECK(meta->metaValue<double>("voxel_size_m") == Approx(0.2));
        CHECK((*meta)["truncation_max_m"] != nullptr);
        CHECK((*meta)["scans_integrated"] == nullptr);
    }
    for (const auto& [grid, voxels] : vdbVoxels(root / "whole" / "map.vdb")) {
        INFO(grid);
        Voxels in_tiles;
        for (const auto& [c, v] : voxels) {
            if (cells.count({floorDiv(c[ax0], tile_vox), floorDiv(c[ax1], tile_vox)})) in_tiles[c] = v;
        }
        REQUIRE(joined.count(grid) == 1);
        CHECK(joined[grid] == in_tiles);
        if (grid == "surface") {
            CHECK(per_tile["counts"]["active_voxels"].get<std::size_t>() == in_tiles.size());
            CHECK(map_voxels == in_tiles.size());
            // Only tiles without a core face leave voxels out.
            CHECK(in_tiles.size() > voxels.size() * 9 / 10);
        }
    }
    CHECK(joined.size() == 3);  // surface, weight, truncation

    // The leaves behind the sensor left memory while the scans came in.
    CHECK(per_tile["tiling"]["map_vdb"] == "per_tile");
    CHECK(per_tile["tiling"]["map_drop"]["leaves_dropped"].get<std::size_t>() > 0);
    CHECK(per_tile["tiling"]["map_drop"]["reader_cells"] == 2);  // (15 + 40 voxels) / 32
    CHECK(whole["tiling"]["map_vdb"] == "whole");
    CHECK_FALSE(whole["tiling"].contains("map_drop"));
}

TEST_CASE("tiling.map_vdb takes whole or per_tile", "[tiles][config]") {
    const fs::path root = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "tile_map_vdb_config";
    std::string message;
    try {
        Pipeline::fromString(yaml(", map_vdb: tiles"), "bad.yaml", root);
    } catch (const ConfigError& e) {
        message = e.what();
    }
    INFO(message);
    CHECK(message.find("map_vdb") != std::string::npos);
    CHECK(message.find("'tiles'") != std::string::npos);
}
