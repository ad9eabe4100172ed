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
    std::vector<std::string> plugin_specs;
    std::vector<std::filesystem::path> plugin_files;
    std::vector<std::string> overrides;
    std::vector<PipelineStage> stages;
};

namespace detail {
/// The layers an opened dataset provides: scans, plus images / semantic_images when present.
std::vector<std::string> datasetLayers(const Dataset& dataset);
/// Writes map.vdb / mesh.ply as `output` says and adds their counts to the report.
void writePipelineOutputs(class Context& ctx, const OutputConfig& output, Report& report);
}  // namespace detail

}  // namespace vdbmap
