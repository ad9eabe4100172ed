// SPDX-License-Identifier: Apache-2.0
#include <tbb/global_control.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "Commands.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/ProcessGroup.h"
#include "vdbmap/pipeline/Report.h"

namespace {

struct RunArgs {
    std::string config;
    std::string output_dir;
    std::vector<std::string> sets;
    int threads = 0;
    bool quiet = false;
    bool check_only = false;
    bool resume = false;
};

/// The number of processes an MPI launcher started this one among: OMPI_COMM_WORLD_SIZE
/// (Open MPI's mpirun) or PMI_SIZE (MPICH's and Intel MPI's), and the variable that said so;
/// {1, ""} outside mpirun.
std::pair<long, std::string> launcherWorldSize() {
    for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
        const char* value = std::getenv(var);
        if (value == nullptr) continue;
        char* end = nullptr;
        const long n = std::strtol(value, &end, 10);
        if (end != value && *end == '\0' && n > 1) return {n, var};
    }
    return {1, ""};
}

/// `mpirun -np N vdbmap run` would start N independent full runs on one output folder (all but
/// one die on its lock): stop before anything runs and name the distributed command.
void refuseMpiLaunch() {
    const auto [size, var] = launcherWorldSize();
    if (size <= 1) return;
    throw vdbmap::ConfigError(
        "vdbmap run: started by an MPI launcher as one of " + std::to_string(size) +
        " processes (" + var + "=" + std::to_string(size) +
        "); each would run the whole pipeline. For a distributed run use `mpirun -np " +
        std::to_string(size) + " vdbmap-mpi run CONFIG` (docs/tiling.md); run `vdbmap run` "
        "without mpirun for a single process");
}

int runPipeline(const RunArgs& args, vdbmap::ProcessGroup* group) {
    if (group == nullptr) refuseMpiLaunch();
    // Processes other than 0 of a distributed run report only warnings and errors.
    const bool quiet = args.quiet || (group != nullptr && group->rank() != 0);
    if (quiet) vdbmap::setLogLevel(vdbmap::LogLevel::Warn);
    // The app sets the thread count once; library code only uses TBB.
    std::unique_ptr<tbb::global_control> threads;
    if (args.threads > 0) {
        threads = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(args.threads));
    }
    auto pipeline = vdbmap::Pipeline::fromFile(args.config, args.sets);
    if (args.check_only) {
        vdbmap::logInfo(args.config + ": OK (" + std::to_string(pipeline->numStages()) +
                        " stages checked, nothing run)");
        return 0;
    }
    const std::filesystem::path out =
        args.output_dir.empty() ? std::filesystem::path(pipeline->outputConfig().dir)
                                : std::filesystem::path(args.output_dir);
    pipeline->setResume(args.resume);
    vdbmap::Report report;
    if (group != nullptr) {
        pipeline->run(out, report, quiet, *group);
    } else {
        pipeline->run(out, report, quiet);
    }
    vdbmap::logInfo("done: outputs in " + out.string() +
                    (pipeline->outputConfig().write_report ? " (report.json)" : ""));
    return 0;
}

}  // namespace

void addRunCommand(CLI::App& app, int& exit_code, vdbmap::ProcessGroup* group) {
    auto args = std::make_shared<RunArgs>();
    CLI::App* run = app.add_subcommand("run", "Run a YAML pipeline (see config/ for examples)");
    run->add_option("config", args->config, "Pipeline file (YAML)")->required();
    run->add_option("-o,--output", args->output_dir,
                    "Output folder (default: output.dir of the config, else ./out)");
    run->add_option("--set", args->sets,
                    "Override an option: dataset.<key>=v, output.<key>=v, stages.<i>.<key>=v "
                    "or <stage>.<key>=v (value parsed as YAML); repeatable")
        ->allow_extra_args(false);
    run->add_option("--threads", args->threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 4096));
    run->add_flag("-q,--quiet", args->quiet, "Only warnings and errors; no progress bars");
    run->add_flag("--resume", args->resume,
                  "Tiled runs: keep the tiles an interrupted (or earlier) run in the output "
                  "folder finished whose inputs and files still match its journal "
                  "(journal.jsonl), redo the others (docs/tiling.md, Resume)");
    run->add_flag("--check", args->check_only,
                  "Load and check the config (keys, types, plugins, layers) without running");
    run->callback([args, &exit_code, group] { exit_code = runPipeline(*args, group); });
}
