// SPDX-License-Identifier: Apache-2.0
// The tiled part of Pipeline::run (issue 13): the mesh stages once per ground tile.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <system_error>
#include <tuple>

#include "pipeline/ContextBuilder.h"
#include "pipeline/TileStream.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/VdbIO.h"
#include "vdbmap/map/VoxelMap.h"
#include "pipeline/TileTasks.h"
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

/// report.json: each planned tile that was worked in pieces gets, in "tiling.plan", its
/// `split_estimate_bytes` (the estimated peak that exceeded the budget) and `pieces` (those
/// with faces); "tiling.split_tiles" counts them.
void reportSplits(const nlohmann::json& report_tiles, Report& report) {
    std::map<std::string, std::pair<std::size_t, std::vector<std::string>>> split;
    for (const auto& [name, tile] : report_tiles.items()) {
        if (!tile.contains("split_estimates_bytes")) continue;  // not over the budget
        auto& entry = split[tile["piece_of"].get<std::string>()];
        entry.first = tile["split_estimates_bytes"].at(0).get<std::size_t>();
        entry.second.push_back(name);
    }
    report.set({"tiling", "split_tiles"}, split.size());
    if (split.empty()) return;
    const std::string plan_text = report.getJson({"tiling", "plan"});
    nlohmann::json plan = plan_text.empty() || plan_text == "null" ? nlohmann::json::array()
                                                                   : nlohmann::json::parse(plan_text);
    for (auto& planned : plan) {
        const auto it = split.find(planned.value("name", ""));
        if (it == split.end()) continue;
        planned["split_estimate_bytes"] = it->second.first;
        planned["pieces"] = it->second.second;
    }
    if (!plan.empty()) report.setJson({"tiling", "plan"}, plan.dump());
}

}  // namespace

TileRun::TileRun(std::vector<PipelineStage>& stages, std::size_t first, std::size_t async_from,
                 const OutputConfig& output, Context& ctx, std::shared_ptr<const Tile> tile,
                 long finished_after_frame, bool memory_window, bool tile_map_vdb)
    : stages_(stages), first_(first), async_from_(std::max(first, async_from)), output_(output),
      ctx_(ctx), tile_(std::move(tile)), finished_after_frame_(finished_after_frame),
      memory_window_(memory_window), tile_map_vdb_(tile_map_vdb),
      dir_(ctx.outputDir() / "tiles" / tile_->name()) {}

TileRun::~TileRun() = default;

bool TileRun::runStages(std::size_t from, std::size_t to, std::string& current) {
    for (std::size_t i = from; i < to && !stopped_; ++i) {
        runStage(stages_[i], i, stages_.size(), *tctx_, current, nullptr);
        // A tile with no surface of its own ends here (tiles are created on demand).
        if (tctx_->hasMesh() && coreFaceCount(*tctx_) == 0) stopped_ = true;
    }
    return !stopped_;
}

void TileRun::runMapStages(std::string& current) {
    try {
        std::error_code ec;
        // Files an earlier attempt at this tile left (a killed or changed run) would otherwise
        // stay in its folder and its index entry. The run holds the folder's lock.
        fs::remove_all(dir_, ec);
        fs::create_directories(dir_, ec);
        if (ec) throw IoError(dir_.string() + ": cannot create the tile folder: " + ec.message());
        if (memory_window_) resetPeakMemoryWindow();
        rss_before_ = currentRssBytes();
        timer_.reset();
        cpu_before_ = processCpuTimeS();
        tctx_ = ContextBuilder::tileContext(ctx_, dir_, report_, tile_);
        runStages(first_, async_from_, current);
        if (tile_map_vdb_ && !stopped_ && output_.write_map && ctx_.hasMap()) writeTileMap();
        // The later stages may run beside the integration: they get a map without voxels (its
        // voxel size and transform only), never the map being integrated (docs/tiling.md).
        if (ctx_.hasMap()) {
            ContextBuilder::setMap(*tctx_, std::make_shared<VoxelMap>(ctx_.map().voxelSize()));
        }
    } catch (const std::exception& e) {
        const std::string stage = current;
        current = "tile " + tile_->name() + " / " + current;
        rethrowInTile(e, tile_->name(), stage);
    }
}

void TileRun::writeTileMap() {
    Timer timer;
    const MeshRegion& core = tile_->region;
    const auto in_core = [&core](const openvdb::Coord& origin) {
        return core.inCore(origin[core.axes[0]], origin[core.axes[1]]);
    };
    openvdb::MetaMap meta;
    meta.insertMeta("tile", openvdb::StringMetadata(tile_->name()));
    map_voxels_ = writeMapVdbPart(dir_ / "map.vdb", ctx_.map(), in_core, meta);
    map_write_s_ = timer.elapsedSeconds();
}

std::size_t TileRun::estimateBytes() const {
    if (!tctx_ || stopped_) return 0;
    const std::size_t faces = tctx_->hasMesh() ? tctx_->mesh().n_faces() : 0;
    const std::size_t occluder_faces = tctx_->hasMesh() ? tctx_->occluderMesh().n_faces() : 0;
    return estimateTilePeakBytes(faces, occluder_faces, tile_->views.size());
}

std::size_t estimateTilePeakBytes(std::size_t faces, std::size_t occluder_faces, std::size_t views) {
    // The memory a tile's stages add at their peak; checked against the 16 tiles of a 400 m
    // street at 0.10 m run one at a time (docs/benchmarks/scale.md, "Tiles in flight"): real
    // 0.29 to 0.96 times this, never above (a least-squares refit: 1261 B per face, 319 B per
    // occluder face, nothing measurable per view).
    constexpr double kFixed = 64.0 * (1 << 20);
    constexpr double kPerFace = 1200.0;
    constexpr double kPerOccluderFace = 300.0;
    constexpr double kPerView = 2.0 * (1 << 20);
    return static_cast<std::size_t>(kFixed + kPerFace * static_cast<double>(faces) +
                                    kPerOccluderFace * static_cast<double>(occluder_faces) +
                                    kPerView * static_cast<double>(views));
}

TileOutcome TileRun::finish(std::string& current) {
    try {
        return finishStages(current);
    } catch (const std::exception& e) {
        const std::string stage = current;
        current = "tile " + tile_->name() + " / " + current;
        rethrowInTile(e, tile_->name(), stage);
    }
}

TileOutcome TileRun::finishStages(std::string& current) {
    const std::size_t estimate = estimateBytes();
    TileOutcome out;
    out.name = tile_->name();
    out.ix = tile_->ix;
    out.iy = tile_->iy;
    runStages(async_from_, stages_.size(), current);
    if (tctx_->hasMesh()) {
        out.faces = coreFaceCount(*tctx_);
        out.halo_faces = tctx_->mesh().n_faces() - out.faces;
    }
    out.empty = out.faces == 0;
    if (!out.empty && tctx_->hasMesh() && output_.write_mesh) {
        const TriMesh core = coreSubmesh(tctx_->mesh());
        writeMeshPly(dir_ / "mesh.ply", core);
    }
    tctx_.reset();  // the tile's mesh, views and stage state are freed here
    std::error_code ec;
    if (out.empty) {
        fs::remove_all(dir_, ec);
        return out;
    }
    const Tile& tile = *tile_;
    const double seconds = timer_.elapsedSeconds();
    const double cpu_seconds = processCpuTimeS() - cpu_before_;
    const nlohmann::json stage_figures = nlohmann::json::parse(report_.getJson({"stages"}));
    nlohmann::json index = {{"name", tile.name()},
                 {"ix", tile.ix},
                 {"iy", tile.iy},
                 {"bounds_W", boxJson(tile.core_W)},
                 {"halo_bounds_W", boxJson(tile.halo_W)},
                 {"files", filesBelow(dir_, ctx_.outputDir())},
                 {"counts",
                  {{"faces", out.faces},
                   {"halo_faces", out.halo_faces},
                   {"views", tile.views.size()},
                   {"frames", tile.numFrames()}}}};
    nlohmann::json report = {{"frames", tile.numFrames()},
                             {"scan_frames", tile.scan_frames.size()},
                             {"views", tile.views.size()},
                             {"faces", out.faces},
                             {"halo_faces", out.halo_faces},
                             {"finished_after_frame", finished_after_frame_},
                             {"wall_time_s", seconds},
                             {"cpu_time_s", cpu_seconds},
                             {"memory_estimate_bytes", estimate},
                             {"stages", stage_figures}};
    if (tile_map_vdb_ && output_.write_map) {
        index["counts"]["map_voxels"] = map_voxels_;
        report["map_voxels"] = map_voxels_;
        report["map_vdb_write_s"] = map_write_s_;
    }
    if (!tile.piece.empty()) {
        // A piece of a tile over the memory budget (TileStream::splits: the estimates that
        // exceeded it) or cut for balance by the plan (TilePlanOptions::split_for_processes).
        index["piece"] = tile.piece;
        report["piece_of"] = tileName(tile.ix, tile.iy);
        report["piece"] = tile.piece;
        if (!tile.split_estimates_bytes.empty()) {
            report["split_estimates_bytes"] = tile.split_estimates_bytes;
        }
    }
    if (memory_window_) {
        // One tile at a time: the window is this tile's alone.
        const std::size_t peak = windowPeakMemoryBytes();
        report["peak_memory_bytes"] = peak;
        report["memory_added_bytes"] = peak > rss_before_ ? peak - rss_before_ : 0;
    } else {
        report["peak_memory_bytes"] = peakMemoryBytes();
    }
    out.index_json = index.dump();
    out.report_json = report.dump();
    return out;
}

TileOutcome runTile(std::vector<PipelineStage>& stages, std::size_t first,
                    const OutputConfig& output, Context& ctx,
                    const std::shared_ptr<const Tile>& tile, long finished_after_frame,
                    std::string& current) {
    TileRun run(stages, first, stages.size(), output, ctx, tile, finished_after_frame, true);
    run.runMapStages(current);
    return run.finish(current);
}

std::string tilesIndex(std::vector<TileOutcome> outcomes, const TileSummary& summary,
                       const TileGrid& grid, const TilingConfig& tiling, Report& report) {
    // The index does not depend on the order tiles were finished in (or on which process);
    // the pieces of a split tile share its (ix, iy) and are ordered by name.
    std::sort(outcomes.begin(), outcomes.end(), [](const TileOutcome& a, const TileOutcome& b) {
        return std::tie(a.iy, a.ix, a.name) < std::tie(b.iy, b.ix, b.name);
    });
    nlohmann::json index_tiles = nlohmann::json::array();
    nlohmann::json report_tiles = nlohmann::json::object();
    nlohmann::json stage_totals = nlohmann::json::object();
    std::size_t faces = 0, halo_faces = 0, peak_tile = 0, map_voxels = 0;
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
        map_voxels += index_tiles.back()["counts"].value("map_voxels", std::size_t(0));
    }
    report.set({"tiling", "map_vdb"}, tiling.map_vdb);
    if (tiling.mapPerTile()) {
        // The tiles' own map.vdb files hold the map (their cores' leaves).
        report.set({"counts", "active_voxels"}, map_voxels);
        report.set({"counts", "voxel_size_m"}, grid.voxelSize());
    }
    report.setJson({"tiles"}, report_tiles.dump());
    reportSplits(report_tiles, report);
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
