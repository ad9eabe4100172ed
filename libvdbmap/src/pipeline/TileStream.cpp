// SPDX-License-Identifier: Apache-2.0
#include "pipeline/TileStream.h"

#include "pipeline/RunJournal.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/ProcessGroup.h"

namespace vdbmap::detail {
namespace fs = std::filesystem;

TileStream::TileStream(const Setup& setup) : setup_(setup) {
    if (setup_.max_in_flight > 1) {
        // The map grows while tiles are in flight (from the first launch to the last on a
        // streamed run): the budget counts its growth on top of the last sample.
        const Context* ctx = setup_.ctx;
        tasks_ = std::make_unique<TileTasks>(setup_.max_in_flight, setup_.memory_budget_bytes,
                                             [] { return currentRssBytes(); },
                                             [ctx] { return ctx->map().tsdfMemoryBytes(); });
    }
}

TileStream::~TileStream() { abandon(); }

void TileStream::abandon() noexcept {
    if (tasks_) tasks_->abandon();
}

template <typename F>
void TileStream::tasksCall(F&& f) {
    try {
        f();
    } catch (...) {
        const std::string at = tasks_->failedAt();
        if (!at.empty() && setup_.current) *setup_.current = at;
        throw;
    }
}

std::string TileStream::inFlightJson() const {
    nlohmann::json j = {{"max_tiles_in_flight", setup_.max_in_flight},
                        {"memory_budget_bytes", setup_.memory_budget_bytes},
                        {"largest_tile_estimate_bytes", largest_estimate_}};
    if (tasks_) {
        const TileTasks::Figures f = tasks_->figures();
        j["most_tiles_in_flight"] = f.max_in_flight;
        j["largest_estimate_in_flight_bytes"] = f.max_estimate_bytes;
        j["tasks"] = f.tasks;
        j["launches_waited"] = f.waits;
        j["launch_wait_s"] = f.wait_s;
        j["memory_without_tiles_bytes"] = f.base_samples;
        // [rss, allocator bytes in use, allocator free bytes, estimates in flight, memory
        // without tiles counted] per launch.
        j["memory_at_launch_bytes"] = f.at_launch;
    } else {
        j["most_tiles_in_flight"] = outcomes_.empty() && without_faces_ == 0 ? 0 : 1;
    }
    return j.dump();
}

void TileStream::makeGrid() {
    const Context& ctx = *setup_.ctx;
    const double voxel_size_m = ctx.map().voxelSize();
    setup_.tiling->validate(voxel_size_m, *setup_.tiling_where);
    const int up_axis = TileGrid::resolveUpAxis(*setup_.tiling, ctx.hasDataset() ? &ctx.dataset() : nullptr);
    grid_.emplace(*setup_.tiling, voxel_size_m, up_axis);
    logInfo("tiling: tiles of " + std::to_string(grid_->tileSizeM()) + " m, halo " +
            std::to_string(grid_->haloM()) + " m");
}

std::vector<std::size_t> TileStream::begin(const Dataset& dataset, double update_reach_m) {
    makeGrid();
    TilePlanOptions options;
    // A scan changes the map no farther than its range filter plus the update reach.
    options.scan_reach_m = dataset.config().max_range_m + update_reach_m;
    options.max_view_distance_m = setup_.tiling->max_view_distance_m;
    options.processes = setup_.processes;
    options.split_for_processes = static_cast<int>(setup_.tiling->split_for_processes);
    options.stream = setup_.tiling->stream;
    plan_ = planTiles(*grid_, dataset, options);
    if (setup_.process == 0 && plan_->pieces() > 0) {
        logInfo("tiling: tiles cut into " + std::to_string(plan_->pieces()) +
                " pieces to spread their work over " + std::to_string(options.split_for_processes) +
                " processes (tiling.split_for_processes)");
    }
    if (setup_.process == 0 && setup_.processes > static_cast<int>(plan_->tiles.size())) {
        logWarn("tiling: " + std::to_string(setup_.processes) + " processes but only " +
                std::to_string(plan_->tiles.size()) + " tiles within reach of a scan: " +
                std::to_string(setup_.processes - static_cast<int>(plan_->tiles.size())) +
                " process(es) get no tile" +
                (options.split_for_processes <= 1 ? "; tiling.split_for_processes: " +
                                                        std::to_string(setup_.processes) +
                                                        " cuts tiles into pieces for them"
                                                  : std::string()));
    }
    if (setup_.processes > 1 && setup_.previous && setup_.redo_all_reason.empty()) balanceResume();
    for (const PlannedTile& t : plan_->tiles) {
        if (t.process == setup_.process) pending_.push_back(&t);
    }
    frames_ = plan_->framesOf(setup_.process);
    reportPlan();
    if (setup_.tiling->mapPerTile() && !setup_.tiling->merge) countReaders();
    // A process of a distributed run integrates only the points that can reach its tiles
    // (issue 37): the others would cost it integration time for leaves it does not own.
    if (setup_.processes > 1) region_.emplace(*grid_, *plan_, setup_.process, update_reach_m);
    views_ = datasetViews(dataset, false, false);
    logInfo("tiling: " + std::to_string(plan_->tiles.size()) + " tiles within reach of a scan (" +
            std::to_string(options.scan_reach_m) + " m)" +
            (setup_.processes > 1 ? ", " + std::to_string(pending_.size()) + " on process " +
                                        std::to_string(setup_.process) + ", " +
                                        std::to_string(frames_.size()) + " of " +
                                        std::to_string(dataset.numFrames()) + " frames"
                                  : std::string()));
    return frames_;
}

std::vector<std::size_t> TileStream::sharedFrames() const {
    if (!plan_ || setup_.processes <= 1) return {};
    std::vector<std::size_t> all;
    for (const PlannedTile& t : plan_->tiles) all.insert(all.end(), t.scan_frames.begin(), t.scan_frames.end());
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    const std::size_t n = all.size(), p = static_cast<std::size_t>(setup_.processes),
                      me = static_cast<std::size_t>(setup_.process);
    using Diff = std::vector<std::size_t>::difference_type;
    return std::vector<std::size_t>(all.begin() + static_cast<Diff>(n * me / p),
                                    all.begin() + static_cast<Diff>(n * (me + 1) / p));
}

std::vector<std::string> TileStream::allGather(const std::string& mine) const {
    if (!setup_.group) return {mine};
    return setup_.group->allGather(mine);
}

void TileStream::reportPlan() {
    nlohmann::json tiles = nlohmann::json::array();
    for (const PlannedTile& t : plan_->tiles) {
        tiles.push_back({{"name", t.name()},
                         {"process", t.process},
                         {"cost_estimate_s", t.cost},
                         {"weighted_frames", t.weighted_frames},
                         {"views", t.views},
                         {"scan_frames", t.scan_frames.size()},
                         {"first_scan_frame", t.scan_frames.front()},
                         {"last_scan_frame", t.scan_frames.back()},
                         {"finish_frame", t.finish_frame}});
    }
    setup_.ctx->report().setJson({"tiling", "plan"}, tiles.dump());
    // Tiles cut into pieces for balance (TilePlan, split_for_processes): the pieces planned.
    setup_.ctx->report().set({"tiling", "balance_pieces"}, plan_->pieces());
}

void TileStream::balanceResume() {
    // A tile the earlier run finished with the same scans will most likely be kept: its
    // process still integrates its scans (its part of map.vdb) but runs no stage on it. Every
    // process reads the same journal, so every process computes the same assignment.
    constexpr double kKeptCostShare = 0.1;
    std::vector<double> costs;
    std::size_t likely_kept = 0;
    for (const PlannedTile& t : plan_->tiles) {
        const auto it = setup_.previous->tiles.find(t.name());
        const bool kept = it != setup_.previous->tiles.end() &&
                          it->second.inputs.value("scan_frames", "") == scanFramesHash(t.scan_frames);
        likely_kept += kept ? 1 : 0;
        costs.push_back(kept ? t.cost * kKeptCostShare : t.cost);
    }
    const std::vector<int> parts = partitionContiguous(costs, setup_.processes);
    for (std::size_t i = 0; i < parts.size(); ++i) plan_->tiles[i].process = parts[i];
    if (setup_.process == 0) {
        logInfo("tiling: " + std::to_string(likely_kept) + " of " + std::to_string(costs.size()) +
                " planned tiles are in the journal; the others are balanced over the processes");
    }
}

void TileStream::frameIntegrated(std::size_t frame) {
    if (tasks_) tasksCall([&] { tasks_->poll(); });
    while (next_ < pending_.size() && pending_[next_]->finish_frame <= frame) {
        finish(*pending_[next_++], static_cast<long>(frame));
    }
}

void TileStream::finishAll() {
    if (!plan_) {
        // No stage streamed the scans: the tiles of the map's leaves, spread by count.
        makeGrid();
        plan_.emplace();
        for (const Tile& t : grid_->tilesOf(setup_.ctx->map())) {
            PlannedTile p;
            p.ix = t.ix;
            p.iy = t.iy;
            p.cost = 1.0;
            plan_->tiles.push_back(p);
        }
        std::vector<double> costs(plan_->tiles.size(), 1.0);
        const std::vector<int> parts = partitionContiguous(costs, setup_.processes);
        for (std::size_t i = 0; i < parts.size(); ++i) plan_->tiles[i].process = parts[i];
        for (const PlannedTile& t : plan_->tiles) {
            if (t.process == setup_.process) pending_.push_back(&t);
        }
        if (setup_.ctx->hasDataset()) views_ = datasetViews(setup_.ctx->dataset(), false, false);
    }
    while (next_ < pending_.size()) finish(*pending_[next_++], -1);
    if (tasks_) tasksCall([&] { tasks_->waitAll(); });
}

void TileStream::finish(const PlannedTile& planned, long after_frame) {
    Timer timer;
    Context& ctx = *setup_.ctx;
    auto tile = std::make_shared<Tile>(grid_->piece(planned.ix, planned.iy, planned.piece));
    if (!planned.piece.empty() && setup_.previous) removeEarlierWholes(*tile);
    tile->scan_frames = planned.scan_frames;
    tile->max_view_distance_m = setup_.tiling->max_view_distance_m;
    // Tiles are created on demand: a planned tile that no scan gave an observed leaf in its
    // core does not exist.
    if (!grid_->fitToMap(*tile, ctx.map())) {
        ++without_leaves_;
    } else {
        finishTile(std::move(tile), after_frame);
    }
    dropUnread(planned);
    if (setup_.tile_seconds) *setup_.tile_seconds += timer.elapsedSeconds();
}

void TileStream::countReaders() {
    // What finishing a tile reads of the map: fitToMap and the marching cubes over the core
    // and the halo, the occluder mesh over the occluder margin, one voxel beyond for the cubes
    // (one leaf). Plus 4 leaves: a scan's update of a leaf there reads the block statistics
    // of the neighbouring blocks (integrate.atsdf's reach), which must not have been dropped.
    const std::int32_t reach_vox =
        std::max(grid_->haloVoxels(), grid_->occluderVoxels()) + 5 * 8;
    reader_cells_ = static_cast<int>((reach_vox + grid_->tileVoxels() - 1) / grid_->tileVoxels());
    for (const PlannedTile* t : pending_) {
        for (int dy = -reader_cells_; dy <= reader_cells_; ++dy)
            for (int dx = -reader_cells_; dx <= reader_cells_; ++dx) ++readers_[{t->ix + dx, t->iy + dy}];
    }
}

void TileStream::dropUnread(const PlannedTile& planned) {
    if (readers_.empty()) return;
    for (int dy = -reader_cells_; dy <= reader_cells_; ++dy)
        for (int dx = -reader_cells_; dx <= reader_cells_; ++dx) --readers_[{planned.ix + dx, planned.iy + dy}];
    // Only the integrating thread changes the map, between scans; the tiles in flight hold a
    // map without voxels (TileRun::runMapStages). A cell no tile of this process still reads
    // is dropped also when a later scan touches it again (another process's tile there).
    VoxelMap& map = setup_.ctx->map();
    map_bytes_max_ = std::max(map_bytes_max_, map.tsdfMemoryBytes());
    leaves_dropped_ += map.dropLeaves([&](const openvdb::Coord& origin) {
        const auto it = readers_.find(grid_->tileOf(origin));
        return it == readers_.end() || it->second <= 0;
    });
}

std::string TileStream::mapDropJson() const {
    return nlohmann::json({{"leaves_dropped", leaves_dropped_},
                           {"map_tsdf_bytes_max", map_bytes_max_},
                           {"reader_cells", reader_cells_}})
        .dump();
}

bool TileStream::splits(const Tile& tile, std::size_t estimate) const {
    // Only a budget above the estimate's fixed part can be met by smaller pieces.
    return estimate > setup_.memory_budget_bytes &&
           setup_.memory_budget_bytes > estimateTilePeakBytes(0, 0, 0) && grid_->canSplit(tile);
}

void TileStream::finishTile(std::shared_ptr<Tile> tile, long after_frame) {
    Context& ctx = *setup_.ctx;
    if (ctx.hasDataset()) {
        TileGrid::assignViews(*tile, views_, setup_.tiling->max_view_distance_m);
    }
    const nlohmann::json inputs =
        setup_.journal || setup_.previous ? tileInputs(setup_.config_hash, *tile) : nlohmann::json();
    const std::size_t decisions = decisions_.size();
    if (setup_.previous && keep(*tile, inputs)) return;
    const std::size_t async_from = tasks_ ? setup_.async_from : setup_.stages->size();
    auto run = std::make_shared<TileRun>(*setup_.stages, setup_.first, async_from, *setup_.output,
                                         ctx, std::shared_ptr<const Tile>(tile), after_frame,
                                         !tasks_, setup_.tiling->mapPerTile());
    run->runMapStages(*setup_.current);
    const std::size_t estimate = run->estimateBytes();
    if (splits(*tile, estimate)) {
        // Over the budget alone: the tile is worked in pieces instead, each meshed again on
        // its own core with the same halo rule (issue 37). The decision depends only on the
        // tile's mesh, views and the budget, never on what else is in flight.
        run.reset();  // its mesh and occluder mesh
        std::error_code ec;
        fs::remove_all(setup_.ctx->outputDir() / "tiles" / tile->name(), ec);
        decisions_.resize(decisions);  // the pieces are kept or redone, not the tile
        logInfo("tile " + tile->name() + ": estimated peak " + std::to_string(estimate >> 20) +
                " MiB over the budget of " + std::to_string(setup_.memory_budget_bytes >> 20) +
                " MiB: worked in pieces");
        for (Tile& piece : grid_->split(*tile)) {
            piece.split_estimates_bytes = tile->split_estimates_bytes;
            piece.split_estimates_bytes.push_back(estimate);
            auto p = std::make_shared<Tile>(std::move(piece));
            if (!grid_->fitToMap(*p, ctx.map())) continue;  // no observed leaf in its core
            finishTile(std::move(p), after_frame);
        }
        return;
    }
    largest_estimate_ = std::max(largest_estimate_, estimate);
    if (setup_.previous) removeEarlierPieces(tile->name());
    if (!tasks_) {
        completed(run->finish(*setup_.current), inputs);
        run.reset();
        releaseFreedMemory();
    } else {
        tasksCall([&] {
            tasks_->launch(estimate, [this, run, inputs](std::string& at) {
                TileOutcome outcome = run->finish(at);
                completed(std::move(outcome), inputs);
            });
        });
    }
}

void TileStream::removeEarlierPieces(const std::string& name) const {
    // An earlier run in this folder (a resume with a larger budget) may have worked the tile
    // in pieces: their folders would stay beside the whole tile's, in no index.
    const fs::path tiles = setup_.ctx->outputDir() / "tiles";
    std::error_code ec;
    if (!fs::is_directory(tiles, ec)) return;
    const std::string prefix = name + ".";
    std::vector<fs::path> pieces;
    for (fs::directory_iterator it(tiles, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->path().filename().string().rfind(prefix, 0) == 0) pieces.push_back(it->path());
    }
    for (const fs::path& p : pieces) fs::remove_all(p, ec);
}

void TileStream::removeEarlierWholes(const Tile& piece) const {
    // An earlier run in this folder may have worked the tile (or a piece this one was cut
    // from) whole: its folder would stay beside this piece's, in no index.
    const fs::path tiles = setup_.ctx->outputDir() / "tiles";
    std::string name = piece.name();
    std::error_code ec;
    for (std::size_t dot = name.rfind('.'); dot != std::string::npos; dot = name.rfind('.')) {
        name.resize(dot);
        fs::remove_all(tiles / name, ec);
    }
}

void TileStream::completed(TileOutcome outcome, const nlohmann::json& inputs) {
    std::lock_guard<std::mutex> lock(completed_mutex_);
    // Journaled once its files are complete, in whatever order the tiles finish.
    if (setup_.journal) {
        setup_.journal->append(tileEntry(inputs, outcome, setup_.ctx->outputDir()));
        testKillAfterTiles(setup_.journal->appended());
    }
    record(std::move(outcome));
}

void TileStream::record(TileOutcome outcome) {
    if (outcome.empty) {
        ++without_faces_;
    } else {
        outcomes_.push_back(std::move(outcome));
    }
}

bool TileStream::keep(const Tile& tile, const nlohmann::json& inputs) {
    const std::string name = tile.name();
    if (!setup_.redo_all_reason.empty()) {
        decisions_.push_back({name, "redone", setup_.redo_all_reason});
        return false;
    }
    const auto it = setup_.previous->tiles.find(name);
    if (it == setup_.previous->tiles.end()) {
        decisions_.push_back({name, "new", "not finished by the earlier run"});
        return false;
    }
    const std::string why = whyRedo(it->second, inputs, setup_.ctx->outputDir());
    if (!why.empty()) {
        logInfo("tile " + name + ": " + why + ", redoing");
        decisions_.push_back({name, "redone", why});
        return false;
    }
    decisions_.push_back({name, "kept", ""});
    std::lock_guard<std::mutex> lock(completed_mutex_);
    record(it->second.outcome);
    return true;
}

}  // namespace vdbmap::detail
