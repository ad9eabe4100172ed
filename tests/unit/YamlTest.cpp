// SPDX-License-Identifier: Apache-2.0
// Config errors: each names file:line:col, the stage and the valid keys, and is raised before
// any stage runs.
#include <catch2/catch.hpp>

#include "support/TestStages.h"
#include "vdbmap/Error.h"
#include "vdbmap/pipeline/Pipeline.h"

using namespace vdbmap;

namespace {

/// Loads `yaml`, expects ConfigError, returns its message; checks that no stage ran.
std::string configError(const std::string& yaml, const std::vector<std::string>& sets = {}) {
    test::registerTestStages();
    const int runs_before = test::stageRuns();
    std::string message;
    try {
        Pipeline::fromString(yaml, "cfg.yaml", ".", sets);
    } catch (const ConfigError& e) {
        message = e.what();
    }
    CHECK(test::stageRuns() == runs_before);
    INFO(message);
    CHECK_FALSE(message.empty());
    return message;
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("a valid config binds every option", "[yaml]") {
    test::registerTestStages();
    auto p = Pipeline::fromString(R"(stages:
  - stage: test.recorder
    count: 4
    scale_m: 2          # an int where a double is expected is fine
    label: "007"        # quoted: a string
    values: [0.5, 1]
    enabled: false
  - stage: test.reader
output:
  dir: somewhere
  write_map: false
)",
                                  "cfg.yaml", ".");
    REQUIRE(p->numStages() == 2);
    const auto& rec = dynamic_cast<const test::RecorderStage&>(p->stage(0));
    CHECK(rec.count_ == 4);
    CHECK(rec.scale_m_ == 2.0);
    CHECK(rec.label_ == "007");
    CHECK(rec.values_ == std::vector<double>{0.5, 1.0});
    CHECK_FALSE(rec.enabled_);
    CHECK(p->outputConfig().dir == "somewhere");
    CHECK_FALSE(p->outputConfig().write_map);
    CHECK(p->outputConfig().write_mesh);
    CHECK_FALSE(p->hasDataset());
    CHECK(p->stageNames() == std::vector<std::string>{"test.recorder", "test.reader"});
}

TEST_CASE("an unknown stage key gives file:line:col, the stage and the valid keys", "[yaml]") {
    const std::string msg = configError(R"(stages:
  - stage: test.recorder
    count: 1
    scale: 0.5
)");
    CHECK(has(msg, "cfg.yaml:4:5"));
    CHECK(has(msg, "stage 'test.recorder' (stages[0])"));
    CHECK(has(msg, "unknown key 'scale'"));
    CHECK(has(msg, "valid keys: count, scale_m, label, values, enabled"));
}

TEST_CASE("a missing required key is an error", "[yaml]") {
    const std::string msg = configError("stages:\n  - stage: test.recorder\n    label: x\n");
    CHECK(has(msg, "cfg.yaml:2:5"));
    CHECK(has(msg, "missing required key 'count'"));
    CHECK(has(msg, "test.recorder"));
}

TEST_CASE("a wrong type names the expected and the found type", "[yaml]") {
    std::string msg = configError("stages:\n  - stage: test.recorder\n    count: abc\n");
    CHECK(has(msg, "cfg.yaml:3:5"));
    CHECK(has(msg, "key 'count': expected int, found string 'abc'"));
    msg = configError("stages:\n  - stage: test.recorder\n    count: 1.5\n");
    CHECK(has(msg, "expected int, found double 1.5"));
    msg = configError("stages:\n  - stage: test.recorder\n    count: \"3\"\n");
    CHECK(has(msg, "expected int, found string '3'"));
    msg = configError("stages:\n  - stage: test.recorder\n    count: 1\n    values: [1, x]\n");
    CHECK(has(msg, "expected list<double>, found string 'x' at element 1"));
    msg = configError("stages:\n  - stage: test.recorder\n    count: 1\n    enabled: 2\n");
    CHECK(has(msg, "expected bool, found int 2"));
    msg = configError("stages:\n  - stage: test.recorder\n    count: {a: 1}\n");
    CHECK(has(msg, "expected int, found a map"));
}

TEST_CASE("an unknown stage lists the registered stages", "[yaml]") {
    const std::string msg = configError("stages:\n  - stage: test.nope\n");
    CHECK(has(msg, "cfg.yaml:2:5"));
    CHECK(has(msg, "unknown stage 'test.nope'"));
    CHECK(has(msg, "test.recorder"));
}

TEST_CASE("a layer without an earlier writer is an error", "[yaml][layers]") {
    std::string msg = configError("stages:\n  - stage: test.reader\n");
    CHECK(has(msg, "cfg.yaml:2:5"));
    CHECK(has(msg, "stage 'test.reader' (stages[0]) reads layer 'recorded'"));
    // Writer after the reader: the message says so.
    msg = configError(
        "stages:\n  - stage: test.reader\n  - stage: test.recorder\n    count: 1\n");
    CHECK(has(msg, "writes it later"));
    msg = configError("stages:\n  - stage: test.mesh_reader\n");
    CHECK(has(msg, "reads layer 'mesh'"));
    // Scans come from the dataset only.
    msg = configError("stages:\n  - stage: test.scan_reader\n");
    CHECK(has(msg, "reads layer 'scans'"));
}

TEST_CASE("initialize() errors carry the stage location", "[yaml]") {
    const std::string msg = configError("stages:\n  - stage: test.recorder\n    count: -1\n");
    CHECK(has(msg, "cfg.yaml:2:5"));
    CHECK(has(msg, "test.recorder: option 'count' must be >= 0, got -1"));
}

TEST_CASE("structural errors: syntax, top-level keys, stages list, sections", "[yaml]") {
    CHECK(has(configError("stages: [\n  - stage: x\n"), "YAML syntax error"));
    std::string msg = configError("stage:\n  - stage: test.recorder\n");
    CHECK(has(msg, "cfg.yaml:1:1"));
    CHECK(has(msg, "unknown top-level key 'stage'; valid keys: dataset, plugins, stages, output"));
    CHECK(has(configError("output: {dir: x}\n"), "missing required key 'stages'"));
    CHECK(has(configError("stages: []\n"), "non-empty list"));
    CHECK(has(configError("stages:\n  - count: 1\n"), "expected a map with key 'stage: <name>'"));
    CHECK(has(configError("stages:\n  - stage: test.recorder\n    count: 1\noutput:\n  dri: x\n"),
              "output: unknown key 'dri'; valid keys: dir, write_map"));
    CHECK(has(configError("stages:\n  - stage: test.recorder\n    count: 1\ndataset:\n  pth: x\n"),
              "dataset: unknown key 'pth'"));
    CHECK(has(configError("- a\n- b\n"), "expected a map with keys dataset"));
    CHECK(has(configError("stages:\n  - stage: test.recorder\n    count: 1\nplugins: texture\n"),
              "plugins: expected a list"));
}
