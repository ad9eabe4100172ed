// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "vdbmap/Error.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"

using namespace vdbmap;
namespace fs = std::filesystem;

TEST_CASE("report values are set at key paths and read back", "[report]") {
    Report report;
    report.set({"counts", "faces"}, std::size_t{12});
    report.set({"a", "b", "c"}, 0.5);
    report.set({"flag"}, true);
    report.set({"name"}, "x");
    report.stage("integrate.atsdf", "points_dropped", 7);
    CHECK(report.getJson({"counts", "faces"}) == "12");
    CHECK(report.getJson({"a", "b", "c"}) == "0.5");
    CHECK(report.getJson({"flag"}) == "true");
    CHECK(report.getJson({"name"}) == "\"x\"");
    // A stage name with dots stays one key.
    CHECK(report.getJson({"stages", "integrate.atsdf", "points_dropped"}) == "7");
    CHECK(report.getJson({"missing"}) == "null");
    CHECK_THROWS_AS(report.set({"name", "below"}, 1), InvalidInput);
    CHECK_THROWS_AS(report.set({}, 1), InvalidInput);
}

TEST_CASE("report counters add up across threads", "[report]") {
    Report report;
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) {
        threads.emplace_back([&] {
            for (int i = 0; i < 1000; ++i) report.add({"counts", "points"}, 2);
        });
    }
    for (auto& t : threads) t.join();
    CHECK(report.getJson({"counts", "points"}) == "8000");
    report.set({"counts", "text"}, "x");
    CHECK_THROWS_AS(report.add({"counts", "text"}, 1), InvalidInput);
}

TEST_CASE("report builds objects from paths and lists from vectors, without JSON text", "[report]") {
    Report report;
    report.stage("semantic.mrf", "classes", std::vector<std::string>{});  // replaced below
    report.set({"stages", "semantic.mrf", "classes"}, std::vector<std::string>{"road", "car"});
    CHECK(report.getJson({"stages", "semantic.mrf", "classes"}) == R"(["road","car"])");
    report.set({"stages", "texture.mrf", "vignetting_abc", "camera_0"},
               std::vector<double>{0.5, -0.25, 0.0});
    report.stage("x", "ids", std::vector<std::int64_t>{3, -1});
    report.set({"per_class", "7", "name"}, "pole \"a\"");
    report.set({"per_class", "7", "faces"}, std::size_t{4});
    CHECK(report.getJson({"stages", "texture.mrf", "vignetting_abc", "camera_0"}) ==
          "[0.5,-0.25,0.0]");
    CHECK(report.getJson({"stages", "x", "ids"}) == "[3,-1]");
    CHECK(report.getJson({"per_class", "7"}) == R"({"faces":4,"name":"pole \"a\""})");
    // A list is a value: nothing can be set below it.
    CHECK_THROWS_AS(report.set({"stages", "x", "ids", "0"}, 1), InvalidInput);
}

TEST_CASE("setJson takes JSON text and rejects invalid text", "[report]") {
    Report report;
    report.setJson({"config"}, R"({"stages": [1, 2]})");
    CHECK(report.getJson({"config", "stages"}) == "[1,2]");
    CHECK_THROWS_AS(report.setJson({"x"}, "{not json"), InvalidInput);
}

TEST_CASE("report writes valid JSON atomically", "[report]") {
    const fs::path dir = fs::temp_directory_path() / "vdbmap_report_test";
    fs::remove_all(dir);
    Report report;
    reportVersions(report);
    report.set({"counts", "faces"}, 3);
    report.write(dir / "report.json");
    std::ifstream in(dir / "report.json");
    const auto json = nlohmann::json::parse(in);
    CHECK(json["counts"]["faces"] == 3);
    CHECK(json["versions"]["vdbmap"].get<std::string>().size() >= 5);
    CHECK(json["versions"]["openvdb"].get<std::string>().rfind("10.", 0) == 0);
    CHECK(json["versions"].contains("openmesh"));
    CHECK(json["versions"].contains("tbb"));
    CHECK(json["versions"].contains("opencv"));
    CHECK(json["versions"].contains("embree"));
    // Only report.json in the folder: no temporary file left behind.
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        (void)entry;
        ++files;
    }
    CHECK(files == 1);
    fs::remove_all(dir);
}
