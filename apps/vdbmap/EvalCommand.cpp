// SPDX-License-Identifier: Apache-2.0
// Placeholder until the evaluation command lands: `vdbmap eval` exists and fails cleanly.
#include "Commands.h"
#include "vdbmap/Error.h"

void addEvalCommand(CLI::App& app, int& exit_code) {
    CLI::App* cmd = app.add_subcommand("eval", "Evaluate a run against ground truth");
    cmd->allow_extras();
    cmd->callback([&exit_code] {
        exit_code = 1;
        throw vdbmap::Error("vdbmap eval: not implemented in this build");
    });
}
