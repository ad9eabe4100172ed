// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <system_error>

#include "io/OutputLock.h"
#include "pipeline/PipelineImpl.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/map/Layers.h"

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

std::string formatSeconds(double s) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.2f s", s);
    return buffer;
}

}  // namespace

namespace detail {

void runStage(PipelineStage& ps, std::size_t index, std::size_t count, Context& ctx,
              std::string& current, std::string* timings_json) {
    Stage& stage = *ps.stage;
    Report& report = ctx.report();
    current = std::string(stage.name());
    const std::string where = ctx.hasTile() ? " [tile " + ctx.tile().name() + "]" : "";
    logInfo("[" + std::to_string(index + 1) + "/" + std::to_string(count) + "] " + current + where);
    Timer timer;
    try {
        stage.run(ctx);
    } catch (...) {
        report.set({"stages", current, "wall_time_s"}, timer.elapsedSeconds());
        throw;
    }
    const double seconds = timer.elapsedSeconds();
    report.set({"stages", current, "wall_time_s"}, seconds);
    if (timings_json) {
        nlohmann::json timings = nlohmann::json::parse(*timings_json);
        timings.push_back({{"index", index}, {"stage", current}, {"wall_time_s", seconds}});
        *timings_json = timings.dump();
        report.setJson({"timings", "stages"}, *timings_json);
    }
    logInfo(current + where + " done in " + formatSeconds(seconds));
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

}  // namespace detail

void Pipeline::run(const fs::path& output_dir, Report& report, bool quiet) {
    Impl& p = *impl_;
    Timer total;
    report.set({"status", "ok"}, false);
    report.set({"status", "state"}, "running");

    auto writeReport = [&] {
        report.set({"peak_memory_bytes"}, peakMemoryBytes());
        report.set({"timings", "total_s"}, total.elapsedSeconds());
        if (p.output.write_report) report.write(output_dir / "report.json");
    };

    // Before anything is written: a second run on the same folder is refused here and must
    // not overwrite the first one's report.json.
    std::error_code dir_ec;
    fs::create_directories(output_dir, dir_ec);
    if (dir_ec || !fs::is_directory(output_dir)) {
        throw IoError(output_dir.string() + ": cannot create the output folder: " +
                      dir_ec.message());
    }
    const OutputLock lock(output_dir);
    if (lock.staleFilesRemoved() > 0) {
        logInfo("removed " + std::to_string(lock.staleFilesRemoved()) +
                " temporary file(s) an interrupted run left in " + output_dir.string());
    }

    std::string current = "setup";
    try {
        reportVersions(report);
        report.setJson({"config"}, resolvedConfigJson());
        report.set({"output_dir"}, fs::absolute(output_dir).string());
        Context ctx(output_dir, report, quiet);
        if (p.has_dataset) {
            current = "dataset";
            Timer timer;
            std::shared_ptr<Dataset> dataset = Dataset::open(p.dataset, p.base_dir);
            checkLayers(detail::datasetLayers(*dataset));
            report.set({"counts", "frames"}, dataset->numFrames());
            report.set({"counts", "cameras"}, dataset->cameras().size());
            // DATA.md: a missing image or semantic file is no error, but the run reports it.
            report.set({"counts", "missing_images"}, dataset->missingImages());
            report.set({"counts", "missing_semantic_images"}, dataset->missingSemantics());
            for (std::size_t cam = 0; cam < dataset->cameras().size(); ++cam) {
                report.set({"counts", "missing_images_per_camera", dataset->cameras()[cam].name},
                           dataset->missingImages(cam));
            }
            report.set({"timings", "dataset_open_s"}, timer.elapsedSeconds());
            ctx.setDataset(std::move(dataset));
        }
        const bool tiled = p.tiling.enabled() && firstTiledStage() < p.stages.size();
        if (p.tiling.enabled() && !tiled) {
            logWarn("tiling: no stage works on the mesh layer; the run is not tiled");
        }
        // A tiles.json of an earlier run in this folder must not outlive a failure of this one.
        std::error_code rm_ec;
        fs::remove(output_dir / "tiles.json", rm_ec);
        const std::size_t untiled_end = tiled ? firstTiledStage() : p.stages.size();
        std::string timings = "[]";
        for (std::size_t i = 0; i < untiled_end; ++i) {
            detail::runStage(p.stages[i], i, p.stages.size(), ctx, current, &timings);
        }
        std::string tiles_json;
        if (tiled) {
            tiles_json = detail::runTiledStages(p.stages, untiled_end, p.tiling, p.tiling_where,
                                                p.output, ctx, report, current);
        }
        current = "output";
        detail::writePipelineOutputs(ctx, p.output, report);
        if (tiled) {
            // Last: the index appears only once every file it names is written.
            writeFileAtomically(output_dir / "tiles.json", tiles_json);
            report.set({"outputs", "tiles_index"}, (output_dir / "tiles.json").string());
        }
    } catch (const std::exception& e) {
        report.set({"status", "state"}, "failed");
        report.set({"status", "error"}, std::string(e.what()));
        report.set({"status", "error_type"}, errorKind(e));
        report.set({"status", "failed_at"}, current);
        report.set({"status", "exit_code"}, exitCodeFor(e));
        try {
            writeReport();
        } catch (const std::exception& write_error) {
            logError("could not write report.json: " + std::string(write_error.what()));
        }
        throw;
    }
    report.set({"status", "state"}, "done");
    report.set({"status", "ok"}, true);
    report.set({"status", "exit_code"}, 0);
    writeReport();
}

}  // namespace vdbmap
