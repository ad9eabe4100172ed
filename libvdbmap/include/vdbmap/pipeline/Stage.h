// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <string_view>

#include "vdbmap/Error.h"
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/pipeline/LayerSpec.h"

namespace vdbmap {

class Context;

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
