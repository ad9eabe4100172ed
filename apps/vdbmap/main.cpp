// SPDX-License-Identifier: Apache-2.0
// `vdbmap`: runs YAML pipelines, describes stages, inspects .vdb files, evaluates runs.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "Commands.h"
#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/StageRegistry.h"

int main(int argc, char** argv) {
    CLI::App app{"vdbmap " + std::string(vdbmap::versionString()) +
                 ": Adaptive-TSDF maps, meshes, textured and semantic meshes from LiDAR + cameras"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string(vdbmap::versionString()));
    app.footer(
        "Exit codes: 0 success, 2 usage or configuration error, 1 runtime or input error.");
    int exit_code = 0;
    addRunCommand(app, exit_code);
    addDescribeCommand(app, exit_code);
    addInfoCommand(app, exit_code);
    addEvalCommand(app, exit_code);
    addViewCommand(app, exit_code);
    try {
        addRelocatablePluginDir();
        vdbmap::registerBuiltinStages();
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    } catch (const vdbmap::Error& e) {
        vdbmap::logError(e.what());
        return vdbmap::exitCodeFor(e);
    } catch (const std::exception& e) {
        vdbmap::logError(std::string("unexpected error: ") + e.what());
        return 1;
    }
    return exit_code;
}
