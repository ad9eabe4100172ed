// SPDX-License-Identifier: Apache-2.0
// The tiled part of Pipeline::run (issue 13): the mesh stages once per ground tile.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <system_error>
#include <tuple>

#include "pipeline/ContextBuilder.h"
#include "pipeline/TileStream.h"
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

/// Rethrows `e` as the same error type with the tile and the stage (unless the message
/// already starts with it) named in front: "tile 3_-1: semantic.mrf: ...".
[[noreturn]] void rethrowInTile(const std::exception& e, const std::string& tile,
                                const std::string& stage) {
    const std::string what = e.what();
    const bool named = stage.empty() || what.rfind(stage + ":", 0) == 0;
    const std::string msg = "tile " + tile + ": " + (named ? "" : stage + ": ") + what;
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
/// runTile without the error prefix.
TileOutcome runTileStages(std::vector<PipelineStage>& stages, std::size_t first,
                          const OutputConfig& output, Context& ctx,
                          const std::shared_ptr<const Tile>& tile, long finished_after_frame,
                          std::string& current) {
    const fs::path dir = ctx.outputDir() / "tiles" / tile->name();
    std::error_code ec;
    // Files an earlier attempt at this tile left (a killed or changed run) would otherwise
    // stay in its folder and its index entry. The run holds the folder's lock.
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    if (ec) throw IoError(dir.string() + ": cannot create the tile folder: " + ec.message());
    resetPeakMemoryWindow();
    Timer timer;
    const double cpu_before = processCpuTimeS();
    Report tile_report;
    TileOutcome out;
    out.name = tile->name();
    out.ix = tile->ix;
    out.iy = tile->iy;
    {
        std::unique_ptr<Context> tctx = ContextBuilder::tileContext(ctx, dir, tile_report, tile);
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
    const double cpu_seconds = processCpuTimeS() - cpu_before;
    const nlohmann::json stage_figures = nlohmann::json::parse(tile_report.getJson({"stages"}));
    const nlohmann::json index = {{"name", tile->name()},
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
    const nlohmann::json report = {{"frames", tile->numFrames()},
                                   {"scan_frames", tile->scan_frames.size()},
                                   {"views", tile->views.size()},
                                   {"faces", out.faces},
                                   {"halo_faces", out.halo_faces},
                                   {"finished_after_frame", finished_after_frame},
                                   {"wall_time_s", seconds},
                                   {"cpu_time_s", cpu_seconds},
                                   {"peak_memory_bytes", windowPeakMemoryBytes()},
                                   {"stages", stage_figures}};
    out.index_json = index.dump();
    out.report_json = report.dump();
    return out;
}

}  // namespace

TileOutcome runTile(std::vector<PipelineStage>& stages, std::size_t first,
                    const OutputConfig& output, Context& ctx,
                    const std::shared_ptr<const Tile>& tile, long finished_after_frame,
                    std::string& current) {
    try {
        return runTileStages(stages, first, output, ctx, tile, finished_after_frame, current);
    } catch (const std::exception& e) {
        const std::string stage = current;
        current = "tile " + tile->name() + " / " + current;
        rethrowInTile(e, tile->name(), stage);
    }
}

std::string tilesIndex(std::vector<TileOutcome> outcomes, const TileSummary& summary,
                       const TileGrid& grid, const TilingConfig& tiling, Report& report) {
    // The index does not depend on the order tiles were finished in (or on which process).
    std::sort(outcomes.begin(), outcomes.end(), [](const TileOutcome& a, const TileOutcome& b) {
        return std::tie(a.iy, a.ix) < std::tie(b.iy, b.ix);
    });
    nlohmann::json index_tiles = nlohmann::json::array();
    nlohmann::json report_tiles = nlohmann::json::object();
    nlohmann::json stage_totals = nlohmann::json::object();
    std::size_t faces = 0, halo_faces = 0, peak_tile = 0;
    double cpu_s = 0.0;
    for (const TileOutcome& outcome : outcomes) {
        const nlohmann::json tile_report = nlohmann::json::parse(outcome.report_json);
        cpu_s += tile_report.value("cpu_time_s", 0.0);
        faces += outcome.faces;
        halo_faces += outcome.halo_faces;
        peak_tile = std::max<std::size_t>(peak_tile, tile_report["peak_memory_bytes"]);
        for (const auto& [stage, figures] : tile_report["stages"].items()) {
            if (!figures.contains("wall_time_s")) continue;
            const double s = figures["wall_time_s"];
            const double before =
                stage_totals.contains(stage) ? stage_totals[stage]["wall_time_s"].get<double>() : 0.0;
            stage_totals[stage]["wall_time_s"] = before + s;
        }
        report_tiles[outcome.name] = tile_report;
        index_tiles.push_back(nlohmann::json::parse(outcome.index_json));
    }
    report.setJson({"tiles"}, report_tiles.dump());
    report.set({"tiling", "tiles"}, index_tiles.size());
    report.set({"tiling", "tiles_without_faces"}, summary.without_faces);
    report.set({"tiling", "planned_tiles"}, summary.planned);
    report.set({"tiling", "planned_tiles_without_leaves"}, summary.without_leaves);
    report.set({"tiling", "stream"}, tiling.stream);
    report.set({"tiling", "tile_size_m"}, grid.tileSizeM());
    report.set({"tiling", "halo_m"}, grid.haloM());
    report.set({"tiling", "faces"}, faces);
    report.set({"tiling", "halo_faces"}, halo_faces);
    report.set({"tiling", "max_tile_peak_memory_bytes"}, peak_tile);
    report.set({"tiling", "cpu_time_s"}, cpu_s);
    report.setJson({"tiling", "stages"}, stage_totals.dump());

    nlohmann::json index;
    index["format"] = "vdbmap-tiles";
    index["version"] = 1;
    index["frame"] = "W";
    index["units"] = "m";
    index["voxel_size_m"] = grid.voxelSize();
    index["tile_size_m"] = grid.tileSizeM();
    index["halo_m"] = grid.haloM();
    const char* axis_names[3] = {"x", "y", "z"};
    const int up_axis = grid.upAxis();
    index["up_axis"] = axis_names[up_axis];
    report.set({"tiling", "up_axis"}, axis_names[up_axis]);
    index["max_view_distance_m"] = tiling.max_view_distance_m;
    index["tile_key"] = std::string("<ix>_<iy>: tile (ix, iy) covers [ix, ix + 1) x [iy, iy + 1) ") +
                        "tile sizes along the ground axes " + axis_names[grid.groundAxis(0)] +
                        ", " + axis_names[grid.groundAxis(1)];
    index["tiles"] = index_tiles;
    index["counts"] = {{"tiles", index_tiles.size()}, {"faces", faces}, {"halo_faces", halo_faces}};
    return index.dump(2);
}

}  // namespace vdbmap::detail
