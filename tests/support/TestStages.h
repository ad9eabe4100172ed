// SPDX-License-Identifier: Apache-2.0
#pragma once

// Test-only stages that record what happened, to check that config errors stop a pipeline
// before any stage runs and that options arrive bound.

#include <atomic>
#include <fstream>
#include <string>
#include <vector>

#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Stage.h"
#include "vdbmap/pipeline/StageRegistry.h"

namespace vdbmap::test {

/// How many times any recording stage's run() was called in this process.
inline std::atomic<int>& stageRuns() {
    static std::atomic<int> runs{0};
    return runs;
}

/// `test.recorder`: required int `count`, optional double/string/list options; writes layer
/// "recorded"; run() counts itself and writes its options into the report.
class RecorderStage : public Stage {
public:
    std::string_view name() const override { return "test.recorder"; }
    std::string_view summary() const override { return "Test stage that records its runs"; }
    void declareOptions(OptionSpec& spec) override {
        spec.addRequired("count", "A required integer", count_);
        spec.add("scale_m", "A length", scale_m_, 1.0, "m");
        spec.add("label", "A string", label_, std::string("none"));
        spec.add("values", "A list of doubles", values_, std::vector<double>{1.0, 2.0});
        spec.add("enabled", "A flag", enabled_, true);
    }
    void initialize() override {
        if (count_ < 0) failConfig("option 'count' must be >= 0, got " + std::to_string(count_));
    }
    void declareLayers(LayerSpec& spec) const override { spec.writes("recorded"); }
    void run(Context& ctx) override {
        ++stageRuns();
        ctx.report().stage(std::string(name()), "count", count_);
        ctx.report().stage(std::string(name()), "scale_m", scale_m_);
        ctx.report().stage(std::string(name()), "label", label_);
        ctx.report().add({"counts", "recorded"}, count_);
    }

    int count_ = 0;
    double scale_m_ = 0.0;
    std::string label_;
    std::vector<double> values_;
    bool enabled_ = false;
};

/// `test.reader`: reads layer "recorded"; `fail: true` makes run() throw a runtime error.
class ReaderStage : public Stage {
public:
    std::string_view name() const override { return "test.reader"; }
    void declareOptions(OptionSpec& spec) override {
        spec.add("fail", "Throw from run()", fail_, false);
    }
    void declareLayers(LayerSpec& spec) const override { spec.reads("recorded"); }
    void run(Context& ctx) override {
        ++stageRuns();
        if (fail_) fail("asked to fail");
        std::ofstream(ctx.outputDir() / "reader.txt") << "ran\n";
    }
    bool fail_ = false;
};

/// `test.mesh_reader`: reads layer "mesh" (which only the meshing stage writes).
class MeshReaderStage : public Stage {
public:
    std::string_view name() const override { return "test.mesh_reader"; }
    void declareOptions(OptionSpec&) override {}
    void declareLayers(LayerSpec& spec) const override { spec.reads("mesh"); }
    void run(Context&) override { ++stageRuns(); }
};

/// `test.scan_reader`: reads the dataset layer "scans".
class ScanReaderStage : public Stage {
public:
    std::string_view name() const override { return "test.scan_reader"; }
    void declareOptions(OptionSpec&) override {}
    void declareLayers(LayerSpec& spec) const override { spec.reads("scans"); }
    void run(Context&) override { ++stageRuns(); }
};

/// Registers the test stages once per process.
inline void registerTestStages() {
    static const bool once = [] {
        registerBuiltinStages();
        auto& registry = StageRegistry::instance();
        registry.add<RecorderStage>("test");
        registry.add<ReaderStage>("test");
        registry.add<MeshReaderStage>("test");
        registry.add<ScanReaderStage>("test");
        return true;
    }();
    (void)once;
}

}  // namespace vdbmap::test
