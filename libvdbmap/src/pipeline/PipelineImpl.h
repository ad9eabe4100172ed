// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/pipeline/LayerSpec.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Stage.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap {

/// One configured stage: the instance, its bound options, its layers and where it was declared.
struct PipelineStage {
    std::unique_ptr<Stage> stage;
    OptionSpec spec;
    LayerSpec layers;
    std::string where;  ///< "file:line:col" of the `- stage:` item
    std::string label;  ///< "stage 'integrate.atsdf' (stages[0])"
};

struct Pipeline::Impl {
    std::string source;
    std::filesystem::path base_dir;
    bool has_dataset = false;
    DatasetConfig dataset;
    OptionSpec dataset_spec;
    OutputConfig output;
    OptionSpec output_spec;
    TilingConfig tiling;
    OptionSpec tiling_spec;
    std::string tiling_where;  ///< "file:line:col" of `tiling:` (or the file)
    std::vector<std::string> plugin_specs;
    std::vector<std::filesystem::path> plugin_files;
    std::vector<std::string> overrides;
    std::vector<PipelineStage> stages;
    bool resume = false;  ///< setResume(): keep the tiles an interrupted run finished
};

namespace detail {
/// The layers an opened dataset provides: scans, plus images / semantic_images when present.
std::vector<std::string> datasetLayers(const Dataset& dataset);
/// Writes map.vdb / mesh.ply as `output` says and adds their counts to the report.
/// `map_per_tile` (tiling.map_vdb: per_tile): the tiles wrote their own map.vdb, and the map
/// left in memory is not the whole map: no map.vdb, no map counts here (tilesIndex counts).
void writePipelineOutputs(class Context& ctx, const OutputConfig& output, Report& report,
                          bool map_per_tile = false);

/// Runs stage `index` (of `count`) in `ctx`: logs, times it into ctx.report()
/// (stages.<name>.wall_time_s; `timings` gets an entry if given). `current` names it.
/// `excluded_s` (if given) is a clock of time the stage spent on others' work (tiles a
/// streaming stage finished): its growth during the stage is not the stage's time.
void runStage(PipelineStage& ps, std::size_t index, std::size_t count, class Context& ctx,
              std::string& current, std::string* timings_json,
              const double* excluded_s = nullptr);

}  // namespace detail

}  // namespace vdbmap
