// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include "vdbmap/pipeline/Stage.h"

namespace vdbmap_template {

/// `template.greet`: writes `greeting` `repeat` times into <output>/greetings.txt and records
/// the line count in report.json. A stage is a thin adapter: declare options (bound to
/// members, with defaults and units), check them in initialize(), declare layers, run.
class GreetStage : public vdbmap::Stage {
public:
    std::string_view name() const override { return "template.greet"; }
    std::string_view summary() const override { return "Example plugin stage: writes greetings"; }
    void declareOptions(vdbmap::OptionSpec& spec) override;
    void initialize() override;
    void declareLayers(vdbmap::LayerSpec& spec) const override;
    void run(vdbmap::Context& ctx) override;

private:
    std::string greeting_;
    int repeat_ = 1;
    double indent_m_ = 0.0;
};

}  // namespace vdbmap_template
