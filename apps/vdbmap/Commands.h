// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <CLI/CLI.hpp>

/// Subcommands of the `vdbmap` app. Each adds itself to `app`; its callback sets `exit_code`
/// (0 on success) and lets vdbmap::Error propagate to main(), which maps it to an exit code:
/// 0 success, 2 usage or configuration error (CLI parse errors, ConfigError, PluginError),
/// 1 runtime or input error (IoError, any other exception).

namespace vdbmap {
class ProcessGroup;
}

/// Lets a relocated install find its plugins: `<exe dir>/../lib/vdbmap/plugins`.
void addRelocatablePluginDir();

/// `vdbmap run CONFIG.yaml [-o OUTDIR] [--set key.path=value ...] [--threads N] [--quiet]`.
/// With `group` (vdbmap-mpi) the run is one process of a distributed job: processes other
/// than 0 run quietly (warnings only, no progress bars).
void addRunCommand(CLI::App& app, int& exit_code, vdbmap::ProcessGroup* group = nullptr);
/// `vdbmap describe [STAGE|dataset|output] [--plugin NAME ...]`.
void addDescribeCommand(CLI::App& app, int& exit_code);
/// `vdbmap info FILE.vdb`.
void addInfoCommand(CLI::App& app, int& exit_code);
/// `vdbmap eval ...` (apps/vdbmap/EvalCommand.cpp).
void addEvalCommand(CLI::App& app, int& exit_code);
/// `vdbmap view OUT [--port N] [--no-open]` (apps/vdbmap/ViewCommand.cpp, docs/viewer.md).
void addViewCommand(CLI::App& app, int& exit_code);
