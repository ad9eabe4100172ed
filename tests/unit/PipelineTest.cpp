// SPDX-License-Identifier: Apache-2.0
// Overrides (--set) and the run: stages in order, outputs, report.json (also on failure).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/TestStages.h"
#include "vdbmap/Error.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"

using namespace vdbmap;
namespace fs = std::filesystem;

namespace {

const char* kConfig = R"(stages:
  - stage: test.recorder
    count: 2
    label: from-file
  - stage: test.reader
)";

const test::RecorderStage& recorder(const Pipeline& p) {
    return dynamic_cast<const test::RecorderStage&>(p.stage(0));
}

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    REQUIRE(in.good());
    return nlohmann::json::parse(in);
}

fs::path freshDir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("vdbmap_pipeline_test_" + name);
    fs::remove_all(dir);
    return dir;
}

}  // namespace

TEST_CASE("overrides (--set) by stage index, by stage name and for sections", "[pipeline][set]") {
    test::registerTestStages();
    auto p = Pipeline::fromString(kConfig, "cfg.yaml", ".", {"stages.0.count=5"});
    CHECK(recorder(*p).count_ == 5);
    CHECK(recorder(*p).label_ == "from-file");

    p = Pipeline::fromString(kConfig, "cfg.yaml", ".",
                             {"test.recorder.scale_m=0.05", "test.recorder.values=[3, 4]",
                              "output.dir=elsewhere", "test.reader.fail=true"});
    CHECK(recorder(*p).scale_m_ == 0.05);
    CHECK(recorder(*p).values_ == std::vector<double>{3.0, 4.0});
    CHECK(recorder(*p).count_ == 2);
    CHECK(p->outputConfig().dir == "elsewhere");
    CHECK(dynamic_cast<const test::ReaderStage&>(p->stage(1)).fail_);

    // A required key may come from --set only.
    p = Pipeline::fromString("stages:\n  - stage: test.recorder\n", "cfg.yaml", ".",
                             {"test.recorder.count=9"});
    CHECK(recorder(*p).count_ == 9);

    // dataset.path from --set is relative to the current directory.
    p = Pipeline::fromString(kConfig, "cfg.yaml", "/base", {"dataset.path=seq"});
    REQUIRE(p->hasDataset());
    CHECK(fs::path(p->datasetConfig().path) == fs::absolute("seq"));
}

TEST_CASE("bad --set overrides are config errors", "[pipeline][set]") {
    test::registerTestStages();
    auto load = [](const std::string& set) {
        Pipeline::fromString(kConfig, "cfg.yaml", ".", {set});
    };
    CHECK_THROWS_WITH(load("stages.0.count"), Catch::Contains("expected key.path=value"));
    CHECK_THROWS_WITH(load("stages.7.count=1"), Catch::Contains("out of range"));
    CHECK_THROWS_WITH(load("stages.x.count=1"), Catch::Contains("stages.<index>.<key>"));
    CHECK_THROWS_WITH(load("test.recorder.cnt=1"),
                      Catch::Contains("--set test.recorder.cnt=1") &&
                          Catch::Contains("unknown key 'cnt'"));
    CHECK_THROWS_WITH(load("test.recorder.count=abc"), Catch::Contains("expected int"));
    CHECK_THROWS_WITH(load("nosuch.stage.key=1"), Catch::Contains("unknown path"));
    const char* twice = "stages:\n  - stage: test.recorder\n    count: 1\n"
                        "  - stage: test.recorder\n    count: 2\n";
    CHECK_THROWS_WITH(Pipeline::fromString(twice, "cfg.yaml", ".", {"test.recorder.count=3"}),
                      Catch::Contains("appears 2 times"));
    auto p = Pipeline::fromString(twice, "cfg.yaml", ".", {"stages.1.count=3"});
    CHECK(dynamic_cast<const test::RecorderStage&>(p->stage(1)).count_ == 3);
}

TEST_CASE("run executes stages in order and writes report.json", "[pipeline][report]") {
    test::registerTestStages();
    const fs::path out = freshDir("run");
    auto p = Pipeline::fromString(kConfig, "cfg.yaml", ".", {"stages.0.scale_m=0.5"});
    const int before = test::stageRuns();
    Report report;
    p->run(out, report, true);
    CHECK(test::stageRuns() == before + 2);
    CHECK(fs::exists(out / "reader.txt"));
    CHECK_FALSE(fs::exists(out / "map.vdb"));  // no stage made a map

    const auto json = readJson(out / "report.json");
    CHECK(json["status"]["ok"] == true);
    CHECK(json["status"]["exit_code"] == 0);
    CHECK(json["versions"]["vdbmap"].is_string());
    CHECK(json["versions"]["openvdb"].is_string());
    // The full resolved config: every option of every stage, defaults included.
    const auto& stages = json["config"]["stages"];
    REQUIRE(stages.size() == 2);
    CHECK(stages[0]["stage"] == "test.recorder");
    CHECK(stages[0]["options"]["count"] == 2);
    CHECK(stages[0]["options"]["scale_m"] == 0.5);
    CHECK(stages[0]["options"]["label"] == "from-file");
    CHECK(stages[0]["options"]["values"] == nlohmann::json({1.0, 2.0}));
    CHECK(stages[0]["options"]["enabled"] == true);
    CHECK(stages[1]["options"]["fail"] == false);
    CHECK(json["config"]["output"]["write_mesh"] == true);
    CHECK(json["config"]["overrides"][0] == "stages.0.scale_m=0.5");
    // Counts and values from the stages, timings per stage, peak memory.
    CHECK(json["counts"]["recorded"] == 2);
    CHECK(json["stages"]["test.recorder"]["label"] == "from-file");
    CHECK(json["stages"]["test.recorder"]["wall_time_s"].get<double>() >= 0.0);
    CHECK(json["stages"]["test.reader"]["wall_time_s"].get<double>() >= 0.0);
    REQUIRE(json["timings"]["stages"].size() == 2);
    CHECK(json["timings"]["stages"][1]["stage"] == "test.reader");
    CHECK(json["timings"]["total_s"].get<double>() >= 0.0);
    CHECK(json["peak_memory_bytes"].get<std::int64_t>() > 1000000);
    fs::remove_all(out);
}

TEST_CASE("a failing stage still writes report.json with the error", "[pipeline][report]") {
    test::registerTestStages();
    const fs::path out = freshDir("fail");
    auto p = Pipeline::fromString(kConfig, "cfg.yaml", ".", {"test.reader.fail=true"});
    Report report;
    CHECK_THROWS_WITH(p->run(out, report, true), Catch::Contains("test.reader: asked to fail"));
    const auto json = readJson(out / "report.json");
    CHECK(json["status"]["ok"] == false);
    CHECK(json["status"]["state"] == "failed");
    CHECK(json["status"]["failed_at"] == "test.reader");
    CHECK(json["status"]["exit_code"] == 1);
    CHECK(json["status"]["error"].get<std::string>().find("asked to fail") != std::string::npos);
    CHECK(json["stages"]["test.recorder"]["wall_time_s"].is_number());
    fs::remove_all(out);
}

TEST_CASE("a missing dataset folder fails the run before any stage", "[pipeline]") {
    test::registerTestStages();
    const fs::path out = freshDir("dataset");
    auto p = Pipeline::fromString(
        "dataset:\n  path: /nonexistent/vdbmap/seq\nstages:\n  - stage: test.scan_reader\n",
        "cfg.yaml", ".");
    const int before = test::stageRuns();
    Report report;
    CHECK_THROWS_AS(p->run(out, report, true), Error);
    CHECK(test::stageRuns() == before);
    const auto json = readJson(out / "report.json");
    CHECK(json["status"]["failed_at"] == "dataset");
    CHECK(json["status"]["exit_code"] == 1);
    fs::remove_all(out);
}

TEST_CASE("exit codes: config and plugin errors are 2, others 1", "[pipeline]") {
    CHECK(exitCodeFor(ConfigError("x")) == 2);
    CHECK(exitCodeFor(PluginError("x")) == 2);
    CHECK(exitCodeFor(IoError("x")) == 1);
    CHECK(exitCodeFor(Error("x")) == 1);
    CHECK(exitCodeFor(std::runtime_error("x")) == 1);
}
