// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "vdbmap/Error.h"
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/pipeline/LayerSpec.h"

namespace vdbmap {

class Context;

/// A tile a tiled run finished with faces (its folder is tiles/<name>/ below the output).
struct FinishedTile {
    std::string name;  ///< "<ix>_<iy>"
    int ix = 0, iy = 0;
};

/// One step of a pipeline (PDAL stage lifecycle):
///   construct -> declareOptions -> options bound from YAML -> initialize -> declareLayers
///   -> (all stages checked) -> run.
/// Stages never call each other; they share state only through Context. Algorithms live in
/// free functions / small classes; a stage is a thin adapter around them.
class Stage {
public:
    virtual ~Stage() = default;
    /// "<family>.<name>", e.g. "integrate.atsdf". Must be constant.
    virtual std::string_view name() const = 0;
    /// One line for `vdbmap describe`.
    virtual std::string_view summary() const { return {}; }
    /// Declare every option, bound to a member, with its default.
    virtual void declareOptions(OptionSpec& spec) = 0;
    /// Check option values after binding; throw via failConfig().
    virtual void initialize() {}
    /// Layers read and written (after initialize, so they may depend on options).
    virtual void declareLayers(LayerSpec& spec) const {}
    /// Do the work. Throws vdbmap::Error (use fail()) on runtime problems.
    virtual void run(Context& ctx) = 0;
    /// Once per run, before any stage runs, in the run's context (no dataset, map or mesh
    /// yet; process 0 only in a distributed run): remove run-level files an earlier run left
    /// (a stage's index of all tiles) so that a failed run never leaves a stale one.
    virtual void beginRun(Context& /*ctx*/) {}
    /// Once per run, after every stage ran (untiled) or every tile is finished and written
    /// (tiled), before tiles.json: write run-level files from the per-tile outputs (an index
    /// of all tiles, levels of detail). `tiles`: the finished tiles of all processes, sorted by
    /// (iy, ix); empty in an untiled run. Process 0 only in a distributed run (the other
    /// processes' tiles are on the shared output folder). Throws like run().
    virtual void finishRun(Context& /*ctx*/, const std::vector<FinishedTile>& /*tiles*/) {}

protected:
    /// Throws vdbmap::Error("<stage>: <message>"): a runtime or input problem (exit code 1).
    [[noreturn]] void fail(const std::string& message) const {
        throw Error(std::string(name()) + ": " + message);
    }
    /// Throws vdbmap::ConfigError("<stage>: <message>"): a bad option value (exit code 2).
    [[noreturn]] void failConfig(const std::string& message) const {
        throw ConfigError(std::string(name()) + ": " + message);
    }
};

}  // namespace vdbmap
