// SPDX-License-Identifier: Apache-2.0
#include "GreetStage.h"

#include <vdbmap/core/Log.h>
#include <vdbmap/io/AtomicFile.h>
#include <vdbmap/pipeline/Context.h>
#include <vdbmap/pipeline/Report.h>

namespace vdbmap_template {

void GreetStage::declareOptions(vdbmap::OptionSpec& spec) {
    spec.add("greeting", "Line to write", greeting_,
             std::string("Hello from the template plugin"));
    spec.add("repeat", "How many lines to write", repeat_, 1);
    spec.add("indent_m", "A length option, to show units (unused)", indent_m_, 0.0, "m");
}

void GreetStage::initialize() {
    // failConfig() throws ConfigError("template.greet: ..."): exit code 2, before anything runs.
    if (repeat_ < 0 || repeat_ > 1000) {
        failConfig("option 'repeat' must be in [0, 1000], got " + std::to_string(repeat_));
    }
}

void GreetStage::declareLayers(vdbmap::LayerSpec& spec) const { spec.writes("greetings"); }

void GreetStage::run(vdbmap::Context& ctx) {
    std::string text;
    for (int i = 0; i < repeat_; ++i) text += greeting_ + "\n";
    // Outputs are written atomically: a failed run never leaves a half-written file.
    vdbmap::writeFileAtomically(ctx.outputDir() / "greetings.txt", text);
    ctx.report().stage(std::string(name()), "lines", repeat_);
    vdbmap::logInfo("template.greet wrote " + std::to_string(repeat_) + " lines");
}

}  // namespace vdbmap_template
