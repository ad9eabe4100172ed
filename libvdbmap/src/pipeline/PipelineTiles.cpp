// SPDX-License-Identifier: Apache-2.0
// The tiled part of Pipeline::run (issue 13): the mesh stages once per ground tile.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <system_error>

#include "pipeline/PipelineImpl.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap::detail {
namespace fs = std::filesystem;
namespace {

/// Rethrows `e` as the same error type with the tile named in front.
[[noreturn]] void rethrowInTile(const std::exception& e, const std::string& tile) {
    const std::string msg = "tile " + tile + ": " + e.what();
    if (dynamic_cast<const ConfigError*>(&e)) throw ConfigError(msg);
    if (dynamic_cast<const PluginError*>(&e)) throw PluginError(msg);
    if (dynamic_cast<const IoError*>(&e)) throw IoError(msg);
    if (dynamic_cast<const InvalidInput*>(&e)) throw InvalidInput(msg);
    throw Error(msg);
}

nlohmann::json boxJson(const Box3d& box) {
    return {{"min", {box.min_W.x(), box.min_W.y(), box.min_W.z()}},
            {"max", {box.max_W.x(), box.max_W.y(), box.max_W.z()}}};
}

/// Every file below `dir`, as paths relative to `base`, sorted.
std::vector<std::string> filesBelow(const fs::path& dir, const fs::path& base) {
    std::vector<std::string> files;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (it->is_regular_file()) files.push_back(fs::relative(it->path(), base).generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::size_t coreFaceCount(const Context& ctx) {
    const std::vector<std::uint8_t> halo = ctx.haloFaces();
    return static_cast<std::size_t>(std::count(halo.begin(), halo.end(), 0));
}

/// What one finished tile leaves behind: its index entry and its report entry.
struct TileOutcome {
    bool empty = true;  ///< no core face: nothing written, not in the index
    nlohmann::json index;
    nlohmann::json report;
    std::size_t faces = 0, halo_faces = 0;
};

/// Runs stages[first..] on one tile, writes its core mesh, frees everything but the figures.
TileOutcome runTile(std::vector<PipelineStage>& stages, std::size_t first,
                    const OutputConfig& output, Context& ctx,
                    const std::shared_ptr<const Tile>& tile, std::string& current) {
    const fs::path dir = ctx.outputDir() / "tiles" / tile->name();
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw IoError(dir.string() + ": cannot create the tile folder: " + ec.message());
    resetPeakMemoryWindow();
    Timer timer;
    Report tile_report;
    TileOutcome out;
    {
        std::unique_ptr<Context> tctx = ctx.tileContext(dir, tile_report, tile);
        for (std::size_t i = first; i < stages.size(); ++i) {
            runStage(stages[i], i, stages.size(), *tctx, current, nullptr);
            // A tile with no surface of its own ends here (tiles are created on demand).
            if (tctx->hasMesh() && coreFaceCount(*tctx) == 0) break;
        }
        if (tctx->hasMesh()) {
            out.faces = coreFaceCount(*tctx);
            out.halo_faces = tctx->mesh().n_faces() - out.faces;
        }
        out.empty = out.faces == 0;
        if (!out.empty && tctx->hasMesh() && output.write_mesh) {
            const TriMesh core = coreSubmesh(tctx->mesh());
            writeMeshPly(dir / "mesh.ply", core);
        }
    }  // the tile's mesh, views and stage state are freed here
    if (out.empty) {
        fs::remove_all(dir, ec);
        return out;
    }
    const double seconds = timer.elapsedSeconds();
    const nlohmann::json stage_figures = nlohmann::json::parse(tile_report.getJson({"stages"}));
    out.index = {{"name", tile->name()},
                 {"ix", tile->ix},
                 {"iy", tile->iy},
                 {"bounds_W", boxJson(tile->core_W)},
                 {"halo_bounds_W", boxJson(tile->halo_W)},
                 {"files", filesBelow(dir, ctx.outputDir())},
                 {"counts",
                  {{"faces", out.faces},
                   {"halo_faces", out.halo_faces},
                   {"views", tile->views.size()},
                   {"frames", tile->numFrames()}}}};
    out.report = {{"frames", tile->numFrames()}, {"views", tile->views.size()},
                  {"faces", out.faces},          {"halo_faces", out.halo_faces},
                  {"wall_time_s", seconds},      {"peak_memory_bytes", windowPeakMemoryBytes()},
                  {"stages", stage_figures}};
    return out;
}

}  // namespace

std::string runTiledStages(std::vector<PipelineStage>& stages, std::size_t first,
                           const TilingConfig& tiling, const std::string& tiling_where,
                           const OutputConfig& output, Context& ctx, Report& report,
                           std::string& current) {
    current = "tiling";
    const VoxelMap& map = ctx.map();
    tiling.validate(map.voxelSize(), tiling_where);
    const int up_axis =
        TileGrid::resolveUpAxis(tiling, ctx.hasDataset() ? &ctx.dataset() : nullptr);
    const TileGrid grid(tiling, map.voxelSize(), up_axis);
    std::vector<Tile> tiles = grid.tilesOf(map);
    if (ctx.hasDataset()) TileGrid::assignViews(tiles, ctx.dataset(), tiling.max_view_distance_m);
    logInfo("tiling: " + std::to_string(tiles.size()) + " tiles of " +
            std::to_string(grid.tileSizeM()) + " m, halo " + std::to_string(grid.haloM()) + " m");

    nlohmann::json index_tiles = nlohmann::json::array();
    nlohmann::json report_tiles = nlohmann::json::object();
    nlohmann::json stage_totals = nlohmann::json::object();
    std::size_t faces = 0, halo_faces = 0, empty = 0, peak_tile = 0;
    for (Tile& t : tiles) {
        const auto tile = std::make_shared<const Tile>(std::move(t));
        TileOutcome outcome;
        try {
            outcome = runTile(stages, first, output, ctx, tile, current);
        } catch (const std::exception& e) {
            current = "tile " + tile->name() + " / " + current;
            rethrowInTile(e, tile->name());
        }
        if (outcome.empty) {
            ++empty;
            continue;
        }
        faces += outcome.faces;
        halo_faces += outcome.halo_faces;
        peak_tile = std::max<std::size_t>(peak_tile, outcome.report["peak_memory_bytes"]);
        for (const auto& [stage, figures] : outcome.report["stages"].items()) {
            if (!figures.contains("wall_time_s")) continue;
            const double s = figures["wall_time_s"];
            const double before =
                stage_totals.contains(stage) ? stage_totals[stage]["wall_time_s"].get<double>() : 0.0;
            stage_totals[stage]["wall_time_s"] = before + s;
        }
        report_tiles[tile->name()] = outcome.report;
        index_tiles.push_back(outcome.index);
    }
    tiles.clear();
    current = "tiling";
    report.setJson({"tiles"}, report_tiles.dump());
    report.set({"tiling", "tiles"}, index_tiles.size());
    report.set({"tiling", "tiles_without_faces"}, empty);
    report.set({"tiling", "tile_size_m"}, grid.tileSizeM());
    report.set({"tiling", "halo_m"}, grid.haloM());
    report.set({"tiling", "faces"}, faces);
    report.set({"tiling", "halo_faces"}, halo_faces);
    report.set({"tiling", "max_tile_peak_memory_bytes"}, peak_tile);
    report.setJson({"tiling", "stages"}, stage_totals.dump());

    if (tiling.merge) {
        if (faces > static_cast<std::size_t>(tiling.merge_max_faces)) {
            logWarn("tiling: merge skipped: " + std::to_string(faces) +
                    " faces over all tiles exceed merge_max_faces = " +
                    std::to_string(tiling.merge_max_faces));
            report.set({"tiling", "merged"}, false);
        } else {
            // Today's single outputs: the same stages once on the whole map.
            for (std::size_t i = first; i < stages.size(); ++i) {
                runStage(stages[i], i, stages.size(), ctx, current, nullptr);
            }
            report.set({"tiling", "merged"}, true);
        }
    }

    nlohmann::json index;
    index["format"] = "vdbmap-tiles";
    index["version"] = 1;
    index["frame"] = "W";
    index["units"] = "m";
    index["voxel_size_m"] = map.voxelSize();
    index["tile_size_m"] = grid.tileSizeM();
    index["halo_m"] = grid.haloM();
    const char* axis_names[3] = {"x", "y", "z"};
    index["up_axis"] = axis_names[up_axis];
    report.set({"tiling", "up_axis"}, axis_names[up_axis]);
    index["max_view_distance_m"] = tiling.max_view_distance_m;
    index["tile_key"] = std::string("<ix>_<iy>: tile (ix, iy) covers [ix, ix + 1) x [iy, iy + 1) ") +
                        "tile sizes along the ground axes " + axis_names[up_axis == 0 ? 1 : 0] +
                        ", " + axis_names[up_axis == 2 ? 1 : 2];
    index["tiles"] = index_tiles;
    index["counts"] = {{"tiles", index_tiles.size()}, {"faces", faces}, {"halo_faces", halo_faces}};
    return index.dump(2);
}

}  // namespace vdbmap::detail
