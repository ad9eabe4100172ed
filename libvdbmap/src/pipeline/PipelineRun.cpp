// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <map>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include <tbb/global_control.h>
#include <system_error>
#include <tuple>

#include "io/OutputLock.h"
#include "pipeline/DatasetReport.h"
#include "pipeline/ContextBuilder.h"
#include "pipeline/MapGather.h"
#include "pipeline/PipelineImpl.h"
#include "pipeline/RunJournal.h"
#include "pipeline/TileStream.h"
#include "pipeline/TileTasks.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/ProcessGroup.h"
#include "vdbmap/dynamic/DynamicPoints.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap {
namespace fs = std::filesystem;

namespace {

const char* errorKind(const std::exception& e) {
    if (dynamic_cast<const ConfigError*>(&e)) return "ConfigError";
    if (dynamic_cast<const PluginError*>(&e)) return "PluginError";
    if (dynamic_cast<const IoError*>(&e)) return "IoError";
    if (dynamic_cast<const InvalidInput*>(&e)) return "InvalidInput";
    if (dynamic_cast<const Error*>(&e)) return "Error";
    return "std::exception";
}

/// Throws an error of the kind errorKind() named (how a failure reaches the other processes).
[[noreturn]] void throwAs(const std::string& kind, const std::string& message) {
    if (kind == "ConfigError") throw ConfigError(message);
    if (kind == "PluginError") throw PluginError(message);
    if (kind == "IoError") throw IoError(message);
    if (kind == "InvalidInput") throw InvalidInput(message);
    throw Error(message);
}

std::string formatSeconds(double s) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.2f s", s);
    return buffer;
}

}  // namespace

namespace detail {

void runStage(PipelineStage& ps, std::size_t index, std::size_t count, Context& ctx,
              std::string& current, std::string* timings_json, const double* excluded_s) {
    Stage& stage = *ps.stage;
    Report& report = ctx.report();
    // `current` may change inside run() (a streaming stage finishes tiles); `name` does not.
    const std::string name(stage.name());
    current = name;
    const std::string where = ctx.hasTile() ? " [tile " + ctx.tile().name() + "]" : "";
    logInfo("[" + std::to_string(index + 1) + "/" + std::to_string(count) + "] " + name + where);
    const double excluded_before = excluded_s ? *excluded_s : 0.0;
    Timer timer;
    // Time the stage spent running others' work (tiles finished inside a streaming stage).
    auto own = [&] { return timer.elapsedSeconds() - (excluded_s ? *excluded_s - excluded_before : 0.0); };
    try {
        stage.run(ctx);
    } catch (...) {
        report.set({"stages", name, "wall_time_s"}, own());
        throw;
    }
    ContextBuilder::stageEnded(ctx);
    current = name;
    const double seconds = own();
    report.set({"stages", name, "wall_time_s"}, seconds);
    if (excluded_s && *excluded_s > excluded_before) {
        report.set({"stages", name, "tiles_finished_inside_s"}, *excluded_s - excluded_before);
    }
    if (timings_json) {
        nlohmann::json timings = nlohmann::json::parse(*timings_json);
        timings.push_back({{"index", index}, {"stage", name}, {"wall_time_s", seconds}});
        *timings_json = timings.dump();
        report.setJson({"timings", "stages"}, *timings_json);
    }
    logInfo(name + where + " done in " + formatSeconds(seconds));
}

std::vector<std::string> datasetLayers(const Dataset& dataset) {
    std::vector<std::string> layers{layers::kScans};
    if (dataset.cameras().empty()) return layers;
    layers.emplace_back(layers::kImages);
    // Semantic images are optional per camera: probe the first frames.
    const std::size_t probe = std::min<std::size_t>(dataset.numFrames(), 5);
    for (std::size_t i = 0; i < probe; ++i) {
        for (std::size_t cam = 0; cam < dataset.cameras().size(); ++cam) {
            if (dataset.semanticPath(i, cam)) {
                layers.emplace_back(layers::kSemanticImages);
                return layers;
            }
        }
    }
    return layers;
}

/// One process's part of Pipeline::run, phase by phase. Every process runs the same phases;
/// agree() is where they learn of each other's failures, so that a failure anywhere fails
/// every process with the first failing process's error, and no tiles.json is written.
class PipelineRunner {
public:
    PipelineRunner(Pipeline::Impl& p, const Pipeline& pipeline, const fs::path& output_dir,
                   Report& report, bool quiet, ProcessGroup& group)
        : p_(p), pipeline_(pipeline), output_dir_(output_dir), report_(report), quiet_(quiet),
          group_(group) {}

    void run() {
        report_.set({"status", "ok"}, false);
        report_.set({"status", "state"}, "running");
        guarded([&] { openOutput(); });
        agree();
        shareJournal();
        agree();
        guarded([&] { compute(); });
        // This process's own work is done: what follows waits for the others first.
        compute_cpu_s_ = processCpuTimeS();
        agree();
        guarded([&] { collect(); });
        agree();
        report_.set({"status", "state"}, "done");
        report_.set({"status", "ok"}, true);
        report_.set({"status", "exit_code"}, 0);
        if (root()) writeReport();
    }

private:
    bool root() const { return group_.rank() == 0; }
    bool distributed() const { return group_.size() > 1; }
    bool tiledRun() const {
        return p_.tiling.enabled() && pipeline_.firstTiledStage() < p_.stages.size();
    }

    void writeReport() {
        report_.set({"peak_memory_bytes"}, peakMemoryBytes());
        report_.set({"timings", "total_s"}, total_.elapsedSeconds());
        report_.set({"timings", "cpu_s"}, processCpuTimeS());
        if (p_.output.write_report) report_.write(output_dir_ / "report.json");
    }

    /// Runs `phase`, keeping its exception for agree().
    template <typename Phase>
    void guarded(Phase&& phase) {
        try {
            phase();
        } catch (const std::exception& e) {
            failure_ = std::current_exception();
            failure_json_ = nlohmann::json{{"kind", errorKind(e)},
                                           {"message", e.what()},
                                           {"at", current_},
                                           {"exit_code", exitCodeFor(e)}}
                                .dump();
        }
    }

    /// Every process learns whether any failed. On a failure: the report gets the first
    /// failing process's error (process 0 writes it), and every process throws: the failing
    /// one its own exception, the others the same kind and message.
    void agree() {
        const std::vector<std::string> all =
            distributed() ? group_.allGather(failure_json_) : std::vector<std::string>{failure_json_};
        int first = -1;
        for (std::size_t r = 0; r < all.size() && first < 0; ++r)
            if (!all[r].empty()) first = static_cast<int>(r);
        if (first < 0) return;
        const nlohmann::json f = nlohmann::json::parse(all[static_cast<std::size_t>(first)]);
        report_.set({"status", "state"}, "failed");
        report_.set({"status", "error"}, f["message"].get<std::string>());
        report_.set({"status", "error_type"}, f["kind"].get<std::string>());
        report_.set({"status", "failed_at"}, f["at"].get<std::string>());
        report_.set({"status", "exit_code"}, f["exit_code"].get<int>());
        if (distributed()) report_.set({"status", "failed_process"}, first);
        if (root()) {
            if (distributed() && first != 0) {
                logInfo("process " + std::to_string(first) + " failed: " +
                        f["message"].get<std::string>());
            }
            try {
                writeReport();
            } catch (const std::exception& write_error) {
                logError("could not write report.json: " + std::string(write_error.what()));
            }
        }
        if (failure_) std::rethrow_exception(failure_);
        throwAs(f["kind"].get<std::string>(), f["message"].get<std::string>());
    }

    /// Phase 1 (process 0): the output folder, its lock, no tiles.json of an earlier run.
    void openOutput() {
        if (!root()) return;
        // Before anything is written: a second run on the same folder is refused here and
        // must not overwrite the first one's report.json.
        std::error_code dir_ec;
        fs::create_directories(output_dir_, dir_ec);
        if (dir_ec || !fs::is_directory(output_dir_)) {
            throw IoError(output_dir_.string() + ": cannot create the output folder: " +
                          dir_ec.message());
        }
        lock_.emplace(output_dir_);
        if (lock_->staleFilesRemoved() > 0) {
            logInfo("removed " + std::to_string(lock_->staleFilesRemoved()) +
                    " temporary file(s) an interrupted run left in " + output_dir_.string());
        }
        // A tiles.json of an earlier run in this folder must not outlive a failure of this one.
        std::error_code rm_ec;
        fs::remove(output_dir_ / "tiles.json", rm_ec);
        // Run-level files of an earlier run (a stage's index of all tiles) must not outlive a
        // failure of this one either.
        Context begin_ctx(output_dir_, report_, quiet_);
        for (PipelineStage& ps : p_.stages) {
            current_ = std::string(ps.stage->name());
            ps.stage->beginRun(begin_ctx);
        }
        current_ = "setup";
        if (tiledRun()) {
            startJournal();
        } else if (p_.resume) {
            logWarn("--resume: the run is not tiled; there is nothing to resume");
        }
    }

    /// Process 0: reads the journal an earlier run left, decides what a resume can keep, and
    /// starts this run's journal: the header, then (resuming with the same configuration) the
    /// earlier entries, each checked again when its tile comes up.
    void startJournal() {
        header_ = JournalHeader::fromResolvedConfig(pipeline_.resolvedConfigJson());
        const std::optional<JournalContents> old = RunJournal::read(output_dir_);
        const fs::path file = output_dir_ / RunJournal::kFileName;
        std::vector<std::string> lines;
        std::string redo_all;
        if (!p_.resume) {
            if (old && !old->finished && !old->tiles.empty()) {
                logInfo(file.string() + " is the journal of an interrupted run (" +
                        std::to_string(old->tiles.size()) +
                        " tiles finished); `vdbmap run --resume` would keep them; starting afresh");
            }
        } else if (!old) {
            logInfo("--resume: no journal (" + file.string() + "); starting afresh");
        } else {
            if (!old->header) {
                redo_all = "the journal has no readable header";
            } else if (old->header->vdbmap != header_.vdbmap) {
                redo_all = "the vdbmap version changed (" + old->header->vdbmap + " -> " +
                           header_.vdbmap + ")";
            } else if (old->header->voxel_size_m != header_.voxel_size_m) {
                redo_all = "voxel_size_m changed (" + nlohmann::json(old->header->voxel_size_m).dump() +
                           " -> " + nlohmann::json(header_.voxel_size_m).dump() + ")";
            } else if (old->header->config_hash != header_.config_hash) {
                std::string diffs;
                for (const std::string& d : configDifferences(old->header->config, header_.config)) {
                    diffs += (diffs.empty() ? "" : "; ") + d;
                }
                redo_all = "the configuration changed (" + diffs +
                           ") and every tile's inputs include it";
            }
            if (redo_all.empty()) {
                for (const auto& entry : old->tiles) lines.push_back(entry.second.line);
            }
            logInfo("--resume: the journal of " +
                    std::string(old->finished ? "a finished" : "an interrupted") + " run, " +
                    std::to_string(old->tiles.size()) + " tiles finished" +
                    (redo_all.empty() ? ": keeping each tile whose inputs and files still match"
                                      : "; " + redo_all + ": redoing every tile"));
        }
        RunJournal::start(output_dir_, header_, lines);
        journal_info_ = nlohmann::json{{"redo_all", redo_all}}.dump();
    }

    /// Every process: what process 0 decided about the journal; opens it for appending and,
    /// resuming, reads the entries process 0 carried over.
    void shareJournal() {
        const std::vector<std::string> all =
            distributed() ? group_.allGather(journal_info_) : std::vector<std::string>{journal_info_};
        guarded([&] {
            if (!tiledRun()) return;
            if (!root()) header_ = JournalHeader::fromResolvedConfig(pipeline_.resolvedConfigJson());
            if (!all.at(0).empty()) {
                redo_all_ = nlohmann::json::parse(all.at(0)).value("redo_all", "");
            }
            journal_.emplace(output_dir_);
            if (p_.resume) {
                previous_ = RunJournal::read(output_dir_);
                if (!previous_) previous_.emplace();
            }
        });
    }

    /// Phase 2: the dataset, the stages (tiles finished as the scans stream in), the rest of
    /// the tiles, and (one process, merge: true) the untiled outputs.
    void compute() {
        current_ = "setup";
        reportVersions(report_);
        report_.setJson({"config"}, pipeline_.resolvedConfigJson());
        report_.set({"output_dir"}, fs::absolute(output_dir_).string());
        if (distributed()) {
            report_.set({"distributed", "processes"}, group_.size());
            report_.set({"distributed", "engine"}, "MPI");
        }
        ctx_.emplace(output_dir_, report_, quiet_);
        if (p_.has_dataset) openDataset();
        const bool tiled = p_.tiling.enabled() && pipeline_.firstTiledStage() < p_.stages.size();
        if (p_.tiling.enabled() && !tiled) {
            logWarn("tiling: no stage works on the mesh layer; the run is not tiled");
        }
        if (distributed() && !tiled) {
            throw ConfigError(p_.source + ": a distributed run needs a tiling: section with "
                              "tile_size_m > 0 and a stage that works on the mesh");
        }
        const std::size_t untiled_end = tiled ? pipeline_.firstTiledStage() : p_.stages.size();
        if (tiled) startTileStream(untiled_end);
        try {
            std::string timings = "[]";
            for (std::size_t i = 0; i < untiled_end; ++i) {
                detail::runStage(p_.stages[i], i, p_.stages.size(), *ctx_, current_, &timings,
                                 &tile_seconds_);
            }
            if (tiled) {
                current_ = "tiling";
                stream_->finishAll();
                current_ = "tiling";
            }
        } catch (...) {
            // Tiles still in flight use the stages and the context: they end first.
            if (stream_) stream_->abandon();
            throw;
        }
        if (tiled) {
            report_.setJson({"tiling", "in_flight"}, stream_->inFlightJson());
            if (p_.tiling.mapPerTile()) report_.setJson({"tiling", "map_drop"}, stream_->mapDropJson());
            if (p_.tiling.merge) mergeUntiled(untiled_end);
        }
    }

    /// The first tiled stage from which on no stage reads the map (a layer an untiled stage
    /// wrote, such as tsdf): those stages may run beside the integration.
    std::size_t asyncFrom(std::size_t first_tiled) const {
        std::set<std::string> map_layers;
        for (std::size_t i = 0; i < first_tiled; ++i) {
            for (const auto& l : p_.stages[i].layers.writtenLayers()) map_layers.insert(l);
        }
        map_layers.erase(layers::kMesh);
        map_layers.insert(layers::kTsdf);
        std::size_t from = first_tiled;
        for (std::size_t i = first_tiled; i < p_.stages.size(); ++i) {
            for (const auto& l : p_.stages[i].layers.readLayers()) {
                if (map_layers.count(l) > 0) from = i + 1;
            }
        }
        return from;
    }

    /// tiling.max_tiles_in_flight (0: the threads the run may use) and the memory budget
    /// (tiling.memory_budget_gb; 0: half of MemAvailable now).
    std::pair<std::size_t, std::size_t> inFlightLimits() const {
        std::size_t n = static_cast<std::size_t>(p_.tiling.max_tiles_in_flight);
        if (n == 0) {
            n = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
        }
        const double gib = 1024.0 * 1024.0 * 1024.0;
        const std::size_t budget = p_.tiling.memory_budget_gb > 0.0
                                       ? static_cast<std::size_t>(p_.tiling.memory_budget_gb * gib)
                                       : memAvailableBytes() / 2;
        return {std::max<std::size_t>(1, n), budget};
    }

    void openDataset() {
        current_ = "dataset";
        Timer timer;
        std::shared_ptr<Dataset> dataset = Dataset::open(p_.dataset, p_.base_dir);
        pipeline_.checkLayers(detail::datasetLayers(*dataset));
        report_.set({"counts", "frames"}, dataset->numFrames());
        report_.set({"counts", "cameras"}, dataset->cameras().size());
        detail::reportDataset(report_, *dataset);
        // docs/DATA.md: a missing image or semantic file is no error, but the run reports it.
        report_.set({"counts", "missing_images"}, dataset->missingImages());
        report_.set({"counts", "missing_semantic_images"}, dataset->missingSemantics());
        for (std::size_t cam = 0; cam < dataset->cameras().size(); ++cam) {
            report_.set({"counts", "missing_images_per_camera", dataset->cameras()[cam].name},
                        dataset->missingImages(cam));
        }
        report_.set({"timings", "dataset_open_s"}, timer.elapsedSeconds());
        ContextBuilder::setDataset(*ctx_, std::move(dataset));
    }

    void startTileStream(std::size_t first_tiled) {
        TileStream::Setup setup;
        setup.stages = &p_.stages;
        setup.first = first_tiled;
        setup.async_from = asyncFrom(first_tiled);
        std::tie(setup.max_in_flight, setup.memory_budget_bytes) = inFlightLimits();
        if (setup.async_from >= p_.stages.size()) setup.max_in_flight = 1;
        logInfo("tiling: up to " + std::to_string(setup.max_in_flight) +
                " tiles in flight, memory budget " +
                std::to_string(setup.memory_budget_bytes / (1024 * 1024)) + " MiB");
        setup.tiling = &p_.tiling;
        setup.tiling_where = &p_.tiling_where;
        setup.output = &p_.output;
        setup.ctx = &*ctx_;
        setup.current = &current_;
        setup.process = group_.rank();
        setup.processes = group_.size();
        setup.group = &group_;
        setup.tile_seconds = &tile_seconds_;
        setup.journal = journal_ ? &*journal_ : nullptr;
        setup.config_hash = header_.config_hash;
        setup.previous = previous_ ? &*previous_ : nullptr;
        setup.redo_all_reason = redo_all_;
        stream_ = std::make_shared<TileStream>(setup);
        ContextBuilder::setScanStream(*ctx_, stream_);
    }

    void mergeUntiled(std::size_t first_tiled) {
        std::size_t faces = 0;
        for (const auto& o : stream_->outcomes()) faces += o.faces;
        if (distributed()) {
            logWarn("tiling: merge skipped: a distributed run has no process with the whole map");
            report_.set({"tiling", "merged"}, false);
        } else if (faces > static_cast<std::size_t>(p_.tiling.merge_max_faces)) {
            logWarn("tiling: merge skipped: " + std::to_string(faces) +
                    " faces over all tiles exceed merge_max_faces = " +
                    std::to_string(p_.tiling.merge_max_faces));
            report_.set({"tiling", "merged"}, false);
        } else {
            // Today's single outputs: the same stages once on the whole map.
            for (std::size_t i = first_tiled; i < p_.stages.size(); ++i) {
                detail::runStage(p_.stages[i], i, p_.stages.size(), *ctx_, current_, nullptr,
                                 nullptr);
            }
            report_.set({"tiling", "merged"}, true);
        }
        ContextBuilder::setScanStream(*ctx_, nullptr);
    }

    /// Phase 3: process 0 gathers the tiles and the map parts, writes map.vdb (and mesh.ply),
    /// then tiles.json, last.
    void collect() {
        current_ = "output";
        const nlohmann::json mine = processSummary();
        const std::vector<std::string> all =
            distributed() ? group_.allGather(mine.dump()) : std::vector<std::string>{mine.dump()};
        gatherMap();
        if (!root()) return;
        if (distributed()) {
            // Every process left its removed points as a part (integrate.atsdf); one file.
            const std::size_t n = mergeDynamicPointParts(output_dir_, group_.size());
            if (fs::exists(output_dir_ / "dynamic_points.ply")) {
                report_.set({"outputs", "dynamic_points"}, (output_dir_ / "dynamic_points.ply").string());
                report_.set({"counts", "dynamic_points"}, n);
            }
        }
        std::vector<TileOutcome> outcomes;
        TileSummary summary;
        nlohmann::json processes = nlohmann::json::array();
        for (const std::string& text : all) {
            nlohmann::json s = nlohmann::json::parse(text);
            for (const auto& o : s["outcomes"]) {
                TileOutcome t;
                t.name = o["name"];
                t.ix = o["ix"];
                t.iy = o["iy"];
                t.faces = o["faces"];
                t.halo_faces = o["halo_faces"];
                t.index_json = o["index"];
                t.report_json = o["report"];
                t.empty = false;
                outcomes.push_back(std::move(t));
            }
            summary.without_faces += s["tiles_without_faces"].get<std::size_t>();
            summary.without_leaves += s["planned_tiles_without_leaves"].get<std::size_t>();
            summary.planned = s["planned_tiles"];
            s.erase("outcomes");
            processes.push_back(s);
        }
        if (distributed()) report_.setJson({"distributed", "process"}, processes.dump());
        if (!distributed()) {
            detail::writePipelineOutputs(*ctx_, p_.output, report_, stream_ && p_.tiling.mapPerTile());
        }
        finishStages(outcomes);
        if (stream_) {
            const std::string index =
                tilesIndex(std::move(outcomes), summary, stream_->grid(), p_.tiling, report_);
            // Last: the index appears only once every file it names is written.
            writeFileAtomically(output_dir_ / "tiles.json", index);
            report_.set({"outputs", "tiles_index"}, (output_dir_ / "tiles.json").string());
            if (p_.resume) reportResume(all);
            if (journal_) journal_->append({{"end", true}});
        }
    }

    /// Process 0: every stage's finishRun (run-level files from the per-tile outputs), after
    /// every tile of every process is written and before tiles.json.
    void finishStages(const std::vector<TileOutcome>& outcomes) {
        std::vector<FinishedTile> tiles;
        for (const TileOutcome& o : outcomes) tiles.push_back({o.name, o.ix, o.iy});
        std::sort(tiles.begin(), tiles.end(), [](const FinishedTile& a, const FinishedTile& b) {
            return std::tie(a.iy, a.ix, a.name) < std::tie(b.iy, b.ix, b.name);
        });
        for (PipelineStage& ps : p_.stages) {
            current_ = std::string(ps.stage->name());
            ps.stage->finishRun(*ctx_, tiles);  // the stage reports its own figures
        }
        current_ = "output";
    }

    /// report.json "resume": what the resumed run did with each tile, and why.
    void reportResume(const std::vector<std::string>& summaries) {
        nlohmann::json tiles = nlohmann::json::object();
        std::map<std::string, std::size_t> counts{{"kept", 0}, {"redone", 0}, {"new", 0}};
        for (const std::string& text : summaries) {
            const nlohmann::json summary = nlohmann::json::parse(text);
            for (const auto& d : summary["resume"]) {
                const std::string action = d["action"];
                ++counts[action];
                nlohmann::json entry = {{"action", action}};
                if (!d["reason"].get<std::string>().empty()) entry["reason"] = d["reason"];
                tiles[d["name"].get<std::string>()] = entry;
            }
        }
        nlohmann::json resume = {{"journal", RunJournal::kFileName},
                                 {"kept", counts["kept"]},
                                 {"redone", counts["redone"]},
                                 {"new", counts["new"]},
                                 {"tiles", tiles}};
        if (!redo_all_.empty()) resume["redo_all"] = redo_all_;
        report_.setJson({"resume"}, resume.dump());
        logInfo("resume: " + std::to_string(counts["kept"]) + " tiles kept, " +
                std::to_string(counts["redone"]) + " redone, " + std::to_string(counts["new"]) +
                " not finished before");
    }

    /// What this process tells process 0: its finished tiles and its figures.
    nlohmann::json processSummary() const {
        nlohmann::json s;
        s["process"] = group_.rank();
        s["outcomes"] = nlohmann::json::array();
        s["tiles_without_faces"] = stream_ ? stream_->tilesWithoutFaces() : 0;
        s["planned_tiles_without_leaves"] = stream_ ? stream_->tilesWithoutLeaves() : 0;
        s["planned_tiles"] = stream_ && stream_->begun() ? stream_->plan().tiles.size() : 0;
        s["tiles"] = stream_ ? stream_->outcomes().size() : 0;
        s["frames_integrated"] = stream_ && stream_->begun() ? stream_->frames().size() : 0;
        s["tiles_s"] = tile_seconds_;
        // What this process integrated (issue 37: the points a rank's tiles need; null
        // without an integrate.atsdf stage).
        for (const char* key : {"points_integrated", "dropped_outside_process_tiles", "seconds"}) {
            s[std::string("integrate_") + key] =
                nlohmann::json::parse(report_.getJson({"stages", "integrate.atsdf", key}));
        }
        s["dynamic_removal_seconds"] = nlohmann::json::parse(
            report_.getJson({"stages", "integrate.atsdf", "dynamic_removal", "seconds"}));
        s["cpu_time_s"] = processCpuTimeS();
        // Its CPU time when its own work (the stages and its tiles) ended, before it waited
        // for the others: MPI busy-polls while it waits, which counts as CPU time (issue 37).
        s["own_work_cpu_time_s"] = compute_cpu_s_;
        s["wall_time_s"] = total_.elapsedSeconds();
        s["peak_memory_bytes"] = peakMemoryBytes();
        s["resume"] = nlohmann::json::array();
        if (stream_) {
            for (const auto& d : stream_->resumeDecisions()) {
                s["resume"].push_back({{"name", d.name}, {"action", d.action}, {"reason", d.reason}});
            }
        }
        if (stream_) {
            for (const TileOutcome& o : stream_->outcomes()) {
                s["outcomes"].push_back({{"name", o.name},
                                         {"ix", o.ix},
                                         {"iy", o.iy},
                                         {"faces", o.faces},
                                         {"halo_faces", o.halo_faces},
                                         {"index", o.index_json},
                                         {"report", o.report_json}});
            }
        }
        return s;
    }

    /// Distributed runs: every process sends the leaves of its own tiles, process 0 merges
    /// them and writes the one map.vdb.
    void gatherMap() {
        // tiling.map_vdb: per_tile: each process wrote its tiles' own map.vdb; nothing to gather.
        if (!distributed() || !p_.output.write_map || p_.tiling.mapPerTile()) return;
        std::string part;
        if (ctx_ && ctx_->hasMap() && stream_ && stream_->begun()) {
            const TilePlan& plan = stream_->plan();
            const int me = group_.rank();
            std::size_t dropped = 0;
            part = detail::mapPart(ctx_->map(), stream_->grid(),
                                   [&](int ix, int iy) {
                                       const PlannedTile* t = plan.find(ix, iy);
                                       return t != nullptr && t->process == me;
                                   },
                                   &dropped);
        }
        MapAssembler assembler;
        group_.gatherToRoot(std::move(part), [&](int, std::string&& bytes) {
            if (!bytes.empty()) assembler.add(std::move(bytes));
        });
        if (!root() || assembler.empty()) return;
        const fs::path path = output_dir_ / "map.vdb";
        assembler.write(path);
        report_.set({"counts", "active_voxels"}, assembler.activeVoxels());
        report_.set({"counts", "voxel_size_m"}, ctx_->map().voxelSize());
        report_.set({"outputs", "map"}, path.string());
        logInfo("wrote " + path.string());
    }

    Pipeline::Impl& p_;
    const Pipeline& pipeline_;
    const fs::path output_dir_;
    Report& report_;
    const bool quiet_;
    ProcessGroup& group_;
    Timer total_;
    double compute_cpu_s_ = 0.0;  ///< processCpuTimeS() when compute() ended
    std::optional<OutputLock> lock_;
    std::optional<Context> ctx_;
    std::shared_ptr<TileStream> stream_;
    JournalHeader header_;
    std::string journal_info_;  ///< process 0's decision (JSON), shared by shareJournal()
    std::string redo_all_;
    std::optional<RunJournal> journal_;
    std::optional<JournalContents> previous_;
    double tile_seconds_ = 0.0;
    std::string current_ = "setup";
    std::exception_ptr failure_;
    std::string failure_json_;
};

}  // namespace detail

void Pipeline::setResume(bool resume) { impl_->resume = resume; }

void Pipeline::run(const fs::path& output_dir, Report& report, bool quiet) {
    LocalProcessGroup local;
    run(output_dir, report, quiet, local);
}

void Pipeline::run(const fs::path& output_dir, Report& report, bool quiet, ProcessGroup& group) {
    detail::PipelineRunner(*impl_, *this, output_dir, report, quiet, group).run();
}

}  // namespace vdbmap
