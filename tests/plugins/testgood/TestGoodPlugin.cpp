// SPDX-License-Identifier: Apache-2.0
// Test plugin: one stage with options that writes a file and a report counter.
#include <fstream>

#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/plugin/Plugin.h"

namespace {

class EchoStage : public vdbmap::Stage {
public:
    std::string_view name() const override { return "testgood.echo"; }
    std::string_view summary() const override { return "Writes `message` `repeat` times"; }
    void declareOptions(vdbmap::OptionSpec& spec) override {
        spec.add("message", "Text to write", message_, std::string("hello"));
        spec.add("repeat", "How many lines", repeat_, 1);
        spec.add("width_m", "A length, unused", width_m_, 0.5, "m");
    }
    void initialize() override {
        if (repeat_ < 0) failConfig("option 'repeat' must be >= 0, got " + std::to_string(repeat_));
    }
    void declareLayers(vdbmap::LayerSpec& spec) const override { spec.writes("echo"); }
    void run(vdbmap::Context& ctx) override {
        std::ofstream out(ctx.outputDir() / "echo.txt");
        for (int i = 0; i < repeat_; ++i) out << message_ << "\n";
        ctx.report().stage("testgood.echo", "lines", repeat_);
    }

private:
    std::string message_;
    int repeat_ = 0;
    double width_m_ = 0.0;
};

}  // namespace

VDBMAP_PLUGIN("testgood", EchoStage)
