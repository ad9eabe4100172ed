// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <exception>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/io/Dataset.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap {

class OptionSpec;
class ProcessGroup;
class Report;
class Stage;
namespace detail {
class PipelineRunner;
}

/// The optional `output:` section of a pipeline.
struct OutputConfig {
    std::string dir = "out";  ///< output folder when `vdbmap run` has no -o (relative: to the cwd)
    bool write_map = true;    ///< write map.vdb when a stage created a map
    bool write_mesh = true;   ///< write mesh.ply when a stage created a mesh
    bool write_report = true; ///< write report.json (also when a stage fails)

    void declareOptions(OptionSpec& spec);
};

/// A pipeline read from YAML (yaml-cpp stays inside the library):
///
///     dataset: {format: kitti, path: seq}       # optional; DatasetConfig keys
///     plugins: [texture, ./my/vdbmap_plugin_x.so]  # names or paths (relative to the file)
///     stages:                                   # ordered; `stage:` names the stage
///       - stage: integrate.atsdf
///         voxel_size_m: 0.1
///       - stage: mesh.marching_cubes
///     output: {dir: out/run, write_map: true}   # optional; OutputConfig keys
///     tiling: {tile_size_m: 64, halo_m: 4}      # optional; TilingConfig keys
///
/// Loading does every check before anything runs: YAML syntax, unknown keys (with the list of
/// valid keys), missing required keys, wrong types (expected vs found), unknown stages, plugin
/// loading, each stage's initialize(), and the layer check (every layer a stage reads has an
/// earlier writer or comes from the dataset). Errors are ConfigError (PluginError for plugins)
/// with `file:line:col` and the stage.
///
/// Overrides (`vdbmap run --set`) are `path=value`, the value parsed as YAML:
///   `dataset.<key>`, `output.<key>`, `tiling.<key>`, `stages.<index>.<key>`, or `<stage name>.<key>` when that
///   stage appears once (`integrate.atsdf.voxel_size_m=0.05`). A relative `dataset.path` given
///   this way is relative to the current directory.
class Pipeline {
public:
    /// Reads and checks `yaml_file`. Throws ConfigError / PluginError.
    static std::unique_ptr<Pipeline> fromFile(const std::filesystem::path& yaml_file,
                                              const std::vector<std::string>& overrides = {});
    /// Same, from text; `source_name` is used in messages, relative paths resolve against
    /// `base_dir`.
    static std::unique_ptr<Pipeline> fromString(const std::string& yaml_text,
                                                const std::string& source_name,
                                                const std::filesystem::path& base_dir,
                                                const std::vector<std::string>& overrides = {});
    ~Pipeline();
    Pipeline(const Pipeline&) = delete;
    Pipeline& operator=(const Pipeline&) = delete;

    /// The config file (or source name) and the folder relative paths resolve against.
    const std::string& source() const;
    const std::filesystem::path& baseDir() const;

    std::size_t numStages() const;
    /// Stage i in run order.
    const Stage& stage(std::size_t i) const;
    std::vector<std::string> stageNames() const;

    bool hasDataset() const;
    const DatasetConfig& datasetConfig() const;
    const OutputConfig& outputConfig() const;
    const TilingConfig& tilingConfig() const;
    /// Index of the first stage that reads or writes the "mesh" layer (numStages() if none):
    /// in a tiled run, it and every later stage run once per tile.
    std::size_t firstTiledStage() const;
    /// Canonical paths of the plugins named in `plugins:`.
    const std::vector<std::filesystem::path>& pluginFiles() const;

    /// Every option of the dataset, every stage and the output, with its resolved value, as
    /// JSON text (report.json "config").
    std::string resolvedConfigJson() const;

    /// Checks that each layer a stage reads has an earlier writer or is in `dataset_layers`.
    /// Throws ConfigError naming the file, line, stage and layer.
    void checkLayers(const std::vector<std::string>& dataset_layers) const;

    /// Runs the stages in order into `output_dir` (created), then writes map.vdb / mesh.ply
    /// as `output:` says, then report.json. Tiled (`tiling:`): the stages from
    /// firstTiledStage() on run per tile into tiles/<ix>_<iy>/, then tiles.json is written
    /// (last, atomically; never after a failure) (also when something failed: the error goes into the
    /// report, and the exception is rethrown). Opens the dataset first (IoError) and re-checks
    /// the layers with what it really provides. `quiet` turns progress bars off.
    void run(const std::filesystem::path& output_dir, Report& report, bool quiet = false);
    /// The same run as one process of a distributed job (vdbmap-mpi): the tiles are spread
    /// over `group`'s processes (TilePlan), each integrates only the scans its tiles need and
    /// writes its tiles; process 0 writes map.vdb (gathered), tiles.json and report.json. A
    /// failure on any process fails every process (the first failing process's error, same
    /// type) and no tiles.json is written. Needs a tiled pipeline (ConfigError otherwise).
    void run(const std::filesystem::path& output_dir, Report& report, bool quiet,
             ProcessGroup& group);

    /// Makes the next run() of a tiled pipeline resume the run whose journal is in its output
    /// folder (`vdbmap run --resume`, docs/tiling.md "Resume"): every tile whose journal entry
    /// still matches its inputs (configuration, scans, views, bounds) and whose files still
    /// match their sizes and checksums is kept, the others are redone; the final outputs are
    /// those of an uninterrupted run. Without it, a run starts afresh (and says when the folder
    /// holds an interrupted run's journal).
    void setResume(bool resume);

    /// The pipeline's state (opaque: defined in src/pipeline/PipelineImpl.h for the phases of
    /// fromString and run).
    struct Impl;

private:
    friend class detail::PipelineRunner;
    Pipeline();
    std::unique_ptr<Impl> impl_;
};

/// Process exit code for an error (documented in docs/pipelines.md): ConfigError and PluginError ->
/// 2 (usage or configuration), any other exception -> 1 (runtime or input).
int exitCodeFor(const std::exception& error);

/// Fills report "versions": vdbmap, OpenVDB, OpenMesh, TBB, OpenCV, Embree, and the
/// plugin ABI.
void reportVersions(Report& report);

}  // namespace vdbmap
