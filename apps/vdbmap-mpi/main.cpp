// SPDX-License-Identifier: Apache-2.0
// `vdbmap-mpi run CONFIG.yaml ...`: the `vdbmap run` of a tiled pipeline as one process of an
// MPI job (mpirun -np N vdbmap-mpi run ..., or srun on a cluster). The tiles are spread over
// the ranks; rank 0 writes map.vdb, tiles.json and report.json (docs/tiling.md).
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <exception>

#include "../vdbmap/Commands.h"
#include "MpiProcessGroup.h"
#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/StageRegistry.h"

namespace {

/// Parses and runs the command line; returns the exit code. Every rank reaches the same
/// result (Pipeline::run agrees on failures), so only rank 0 prints the error.
int runCommand(int argc, char** argv, vdbmap::MpiProcessGroup& group) {
    CLI::App app{"vdbmap-mpi " + std::string(vdbmap::versionString()) +
                 ": a tiled vdbmap pipeline spread over the ranks of an MPI job"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string(vdbmap::versionString()));
    app.footer("Exit codes (every rank): 0 success, 2 usage or configuration error, 1 runtime "
               "or input error.");
    int exit_code = 0;
    addRunCommand(app, exit_code, &group);
    const bool root = group.rank() == 0;
    if (!root) vdbmap::setLogPrefix("rank " + std::to_string(group.rank()) + ": ");
    try {
        addRelocatablePluginDir();
        vdbmap::registerBuiltinStages();
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = root ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 2);
        return code == 0 ? 0 : 2;
    } catch (const vdbmap::Error& e) {
        if (root) vdbmap::logError(e.what());
        return vdbmap::exitCodeFor(e);
    } catch (const std::exception& e) {
        if (root) vdbmap::logError(std::string("unexpected error: ") + e.what());
        return 1;
    }
    return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
    int provided = 0;
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        vdbmap::logError("vdbmap-mpi: MPI_Init_thread failed");
        return 1;
    }
    int exit_code = 1;
    {
        vdbmap::MpiProcessGroup group;
        exit_code = runCommand(argc, argv, group);
    }
    MPI_Finalize();
    return exit_code;
}
