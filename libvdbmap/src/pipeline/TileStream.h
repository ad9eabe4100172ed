// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/PipelineImpl.h"
#include "vdbmap/pipeline/Report.h"
#include "pipeline/PointRegion.h"
#include "pipeline/ScanStream.h"
#include "pipeline/TileTasks.h"
#include "vdbmap/pipeline/TilePlan.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap {
class Context;
class ProcessGroup;
}

namespace vdbmap::detail {

class RunJournal;
struct JournalContents;

/// What one finished tile leaves behind (JSON text, so that it can travel between processes).
struct TileOutcome {
    std::string name;
    int ix = 0, iy = 0;
    bool empty = true;       ///< no core face: nothing written, not in the index
    std::string index_json;  ///< its tiles.json entry
    std::string report_json; ///< its report.json "tiles" entry
    std::size_t faces = 0, halo_faces = 0;
};

/// Counts over all processes of the tiles that left no output.
struct TileSummary {
    std::size_t planned = 0;         ///< tiles of the plan (within reach of a scan)
    std::size_t without_leaves = 0;  ///< planned, but no observed leaf in the core
    std::size_t without_faces = 0;   ///< observed leaves, but no core face
};

/// tiles.json from the finished tiles of all processes (sorted by (iy, ix): the index does
/// not depend on when or where a tile was finished); the per-tile and total figures go into
/// `report` ("tiles", "tiling").
std::string tilesIndex(std::vector<TileOutcome> outcomes, const TileSummary& summary,
                       const TileGrid& grid, const TilingConfig& tiling, Report& report);

/// Runs stages[first..] on one tile in a context of its own below ctx (tiles/<name>/), writes
/// its core mesh, frees its mesh, views and stage state on return. `finished_after_frame`
/// goes into its report (-1: after the last scan). Errors are rethrown with "tile <name>: "
/// in front, same type.
TileOutcome runTile(std::vector<PipelineStage>& stages, std::size_t first,
                    const OutputConfig& output, Context& ctx,
                    const std::shared_ptr<const Tile>& tile, long finished_after_frame,
                    std::string& current);

/// One tile's stages in two parts (issue 37): runMapStages() runs, on the integrating thread,
/// the stages up to the last one reading a map layer (marching cubes), in the tile's own
/// context below ctx (tiles/<name>/); finish() runs the others (texture, semantic, export) on
/// any thread, with a map of no voxels in the context, writes the core mesh and frees the
/// tile's mesh, views and stage state. Errors are rethrown with "tile <name>: " in front,
/// same type. `memory_window`: the tile runs alone, its report gets its own peak memory.
class TileRun {
public:
    TileRun(std::vector<PipelineStage>& stages, std::size_t first, std::size_t async_from,
            const OutputConfig& output, Context& ctx, std::shared_ptr<const Tile> tile,
            long finished_after_frame, bool memory_window, bool tile_map_vdb = false);
    ~TileRun();
    TileRun(const TileRun&) = delete;
    TileRun& operator=(const TileRun&) = delete;

    void runMapStages(std::string& current);
    /// The estimated peak memory finish() adds (estimateTilePeakBytes of the tile's mesh,
    /// occluder mesh and views); 0 when the tile ended in runMapStages().
    std::size_t estimateBytes() const;
    TileOutcome finish(std::string& current);

private:
    bool runStages(std::size_t from, std::size_t to, std::string& current);
    TileOutcome finishStages(std::string& current);
    /// tiles/<name>/map.vdb: the leaves of the tile's core (tiling.map_vdb: per_tile), final
    /// once the tile is finished; on the integrating thread, before the next scan.
    void writeTileMap();

    std::vector<PipelineStage>& stages_;
    const std::size_t first_, async_from_;
    const OutputConfig& output_;
    Context& ctx_;
    std::shared_ptr<const Tile> tile_;
    const long finished_after_frame_;
    const bool memory_window_;
    const bool tile_map_vdb_;
    const std::filesystem::path dir_;
    std::size_t map_voxels_ = 0;   ///< active voxels of the tile's map.vdb
    double map_write_s_ = 0.0;
    Report report_;
    std::unique_ptr<Context> tctx_;
    bool stopped_ = false;  ///< no core face: the later stages do not run
    Timer timer_;
    double cpu_before_ = 0.0;
    std::size_t rss_before_ = 0;
};

/// The memory (bytes) a tile's stages after marching cubes are estimated to add at their
/// peak, from its faces (core and halo), occluder faces and views (docs/tiling.md).
std::size_t estimateTilePeakBytes(std::size_t faces, std::size_t occluder_faces, std::size_t views);

/// The tiles of one process of a tiled run (issue 13). When the integrating stage begins
/// (Context::beginScanStream) it plans the tiles from the poses (TilePlan), keeps this
/// process's, and returns the frames they need; after each integrated frame it finishes every
/// tile whose finish frame has passed (tiles without observed leaves are dropped, the others
/// fitted to the map, given their views and run by runTile). finishAll() finishes the rest.
class TileStream final : public ScanStream {
public:
    struct Setup {
        std::vector<PipelineStage>* stages = nullptr;
        std::size_t first = 0;  ///< the first tiled stage
        /// The first tiled stage that reads no map layer and none after it does: it and the
        /// later ones run in a task per tile, beside the integration (issue 37).
        std::size_t async_from = 0;
        /// Tiles in flight at most (1: each tile's stages run inside the integrating stage).
        std::size_t max_in_flight = 1;
        std::size_t memory_budget_bytes = 0;
        const TilingConfig* tiling = nullptr;
        const std::string* tiling_where = nullptr;  ///< "file:line:col" of `tiling:`
        const OutputConfig* output = nullptr;
        Context* ctx = nullptr;        ///< the run's context (dataset, map)
        std::string* current = nullptr;  ///< what runs now, for error reports
        int process = 0, processes = 1;
        /// The processes of a distributed run (allGather); nullptr: one process.
        ProcessGroup* group = nullptr;
        /// Time spent finishing tiles is added here (it runs inside the integrating stage).
        double* tile_seconds = nullptr;
        /// Each finished tile is appended here (nullptr: no journal).
        RunJournal* journal = nullptr;
        std::string config_hash;  ///< JournalHeader::config_hash, part of each tile's inputs
        /// A resumed run (--resume): the earlier run's journal; a tile whose entry still holds
        /// is kept instead of run (nullptr: not resuming).
        const JournalContents* previous = nullptr;
        /// A resumed run that keeps no tile: why (the configuration or the version changed).
        std::string redo_all_reason;
    };
    /// What a resumed run did with one tile.
    struct ResumeDecision {
        std::string name;
        std::string action;  ///< "kept", "redone" (its entry did not hold), "new" (no entry)
        std::string reason;
    };
    explicit TileStream(const Setup& setup);
    ~TileStream() override;

    std::vector<std::size_t> begin(const Dataset& dataset, double update_reach_m) override;
    void frameIntegrated(std::size_t frame) override;
    bool begun() const override { return plan_.has_value(); }
    const std::vector<std::size_t>& frames() const override { return frames_; }
    int process() const override { return setup_.process; }
    int processes() const override { return setup_.processes; }
    const PointRegion* pointRegion() const override { return region_ ? &*region_ : nullptr; }
    std::vector<std::size_t> sharedFrames() const override;
    std::vector<std::string> allGather(const std::string& mine) const override;

    /// Finishes every tile not finished yet. Without begin() (no stage integrated scans
    /// through the stream) the tiles are those of the map's leaves, spread over the processes.
    void finishAll();

    /// Waits for the tiles in flight, forgetting their errors (the run fails already).
    void abandon() noexcept;
    /// Tiles in flight: the figures (report.json "tiling.in_flight"), as JSON text.
    std::string inFlightJson() const;
    /// tiling.map_vdb: per_tile: the leaves dropped and the map's largest TSDF size (JSON).
    std::string mapDropJson() const;

    /// The grid (after begin() or finishAll()).
    const TileGrid& grid() const { return *grid_; }
    /// The plan (after begin() or finishAll()).
    const TilePlan& plan() const { return *plan_; }
    /// Finished tiles with faces, in finish order.
    const std::vector<TileOutcome>& outcomes() const { return outcomes_; }
    /// Tiles finished without a core face / planned tiles that got no observed leaf.
    std::size_t tilesWithoutFaces() const { return without_faces_; }
    std::size_t tilesWithoutLeaves() const { return without_leaves_; }
    /// A resumed run: each finished tile's decision, in finish order.
    const std::vector<ResumeDecision>& resumeDecisions() const { return decisions_; }

private:
    void finish(const PlannedTile& planned, long after_frame);
    /// Runs a fitted tile (or piece): kept from the journal, or meshed, then either its other
    /// stages run (in a task with tiles in flight) or, its estimated peak over the budget, it
    /// is split into pieces, each finished the same way.
    void finishTile(std::shared_ptr<Tile> tile, long after_frame);
    /// Whether a tile with this estimated peak is worked in pieces: the estimate exceeds the
    /// memory budget, the budget exceeds the estimate's fixed part, and the tile can be cut.
    bool splits(const Tile& tile, std::size_t estimate) const;
    /// Removes the folders tiles/<name>.* that the run being resumed left when it worked the
    /// tile in pieces (a resume whose budget no longer splits it); called on resumes only.
    void removeEarlierPieces(const std::string& name) const;
    /// Removes the folders of the tile and of the pieces `piece` (a piece cut for balance) was
    /// cut from, that the run being resumed left when it worked them whole; resumes only.
    void removeEarlierWholes(const Tile& piece) const;
    /// report.json "tiling.plan": every planned tile's process, cost estimate and its features.
    void reportPlan();
    /// A distributed resume: the tiles given to the processes again, those the journal will
    /// likely keep at a tenth of their cost, so that the tiles still to do are balanced.
    void balanceResume();
    /// A resumed run: keeps `tile` from the earlier run's journal if its entry holds
    /// (returns true), else records why it is redone.
    bool keep(const Tile& tile, const nlohmann::json& inputs);
    void record(TileOutcome outcome);
    /// A tile's stages are done: journal it, record it (any thread).
    void completed(TileOutcome outcome, const nlohmann::json& inputs);
    /// Runs `f` (a TileTasks call); a tile task's failure gets what it ran as `current`.
    template <typename F>
    void tasksCall(F&& f);
    /// The grid from the tiling config and the map's voxel size (ConfigError for a bad config).
    void makeGrid();
    /// tiling.map_vdb: per_tile: counts, for every tile cell, this process's planned tiles
    /// whose finishing reads its leaves (their core grown by the halo or the occluder margin,
    /// whichever is wider, and one leaf), so that dropUnread() can let the map go behind the
    /// sensor.
    void countReaders();
    /// `planned` is finished: the cells it read have one reader less; the leaves of every
    /// cell no tile still to come reads leave the map (VoxelMap::dropLeaves).
    void dropUnread(const PlannedTile& planned);

    Setup setup_;
    std::optional<TileGrid> grid_;
    std::optional<TilePlan> plan_;
    std::vector<const PlannedTile*> pending_;  ///< this process's tiles, finish order
    std::size_t next_ = 0;
    std::vector<std::size_t> frames_;
    std::optional<PointRegion> region_;  ///< distributed runs: the points that matter here
    std::vector<View> views_;
    std::vector<TileOutcome> outcomes_;
    std::size_t without_faces_ = 0, without_leaves_ = 0;
    std::vector<ResumeDecision> decisions_;
    std::mutex completed_mutex_;  ///< outcomes_, without_faces_, the journal
    std::unique_ptr<TileTasks> tasks_;  ///< max_in_flight > 1
    std::size_t largest_estimate_ = 0;
    /// Per tile cell (ix, iy): this process's planned tiles still to finish that read it;
    /// empty unless the map's leaves are dropped (countReaders).
    std::map<std::pair<int, int>, int> readers_;
    int reader_cells_ = 0;  ///< cells a tile reads on each side of its own
    std::size_t leaves_dropped_ = 0;
    std::size_t map_bytes_max_ = 0;  ///< the map's TSDF bytes before a drop, at most
};

}  // namespace vdbmap::detail
