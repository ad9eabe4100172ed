// SPDX-License-Identifier: Apache-2.0
// Run-time plugins: by path, by name on VDBMAP_PLUGIN_PATH; wrong ABI, a text file, a module
// without the entry symbol and a failing registration are rejected with clear messages.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/StageRegistry.h"
#include "vdbmap/plugin/PluginLoader.h"

using namespace vdbmap;
namespace fs = std::filesystem;

namespace {

const fs::path kPluginDir = fs::path(VDBMAP_BINARY_DIR) / "tests" / "plugins-bin";

fs::path pluginFile(const std::string& name) {
    return kPluginDir / ("vdbmap_plugin_" + name + ".so");
}

std::string loadError(const std::string& spec) {
    try {
        PluginLoader::load(spec);
    } catch (const PluginError& e) {
        return e.what();
    }
    FAIL("no PluginError for " << spec);
    return {};
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("a good plugin loads by path and registers its stage", "[plugin]") {
    registerBuiltinStages();
    REQUIRE(fs::exists(pluginFile("testgood")));
    const fs::path loaded = PluginLoader::load(pluginFile("testgood").string());
    CHECK(loaded == fs::canonical(pluginFile("testgood")));
    REQUIRE(StageRegistry::instance().contains("testgood.echo"));
    // Loading again is a no-op (no duplicate-stage error).
    CHECK(PluginLoader::load(pluginFile("testgood").string()) == loaded);
    const auto entries = StageRegistry::instance().entries();
    for (const auto& entry : entries) {
        if (entry.name == "testgood.echo") {
            CHECK(entry.origin == loaded.string());
            CHECK(entry.summary == "Writes `message` `repeat` times");
        }
    }
    auto stage = StageRegistry::instance().create("testgood.echo");
    OptionSpec spec;
    stage->declareOptions(spec);
    CHECK(spec.keyList() == "message, repeat, width_m");
}

TEST_CASE("a plugin loads by name from VDBMAP_PLUGIN_PATH and runs in a pipeline", "[plugin]") {
    registerBuiltinStages();
    ::setenv("VDBMAP_PLUGIN_PATH", ("/nonexistent/dir:" + kPluginDir.string()).c_str(), 1);
    const auto dirs = PluginLoader::searchPath();
    REQUIRE(dirs.size() >= 2);
    CHECK(dirs[0] == fs::path("/nonexistent/dir"));
    CHECK(dirs[1] == kPluginDir);
    CHECK(PluginLoader::resolve("testgood") == fs::canonical(pluginFile("testgood")));
    const auto names = PluginLoader::discover();
    CHECK(std::find(names.begin(), names.end(), "testgood") != names.end());

    const fs::path out = fs::temp_directory_path() / "vdbmap_plugin_test_run";
    fs::remove_all(out);
    auto pipeline = Pipeline::fromString(
        "plugins: [testgood]\nstages:\n  - stage: testgood.echo\n    message: hi\n    repeat: 3\n",
        "cfg.yaml", ".");
    Report report;
    pipeline->run(out, report, true);
    std::ifstream in(out / "echo.txt");
    std::string line;
    int lines = 0;
    while (std::getline(in, line)) {
        CHECK(line == "hi");
        ++lines;
    }
    CHECK(lines == 3);
    CHECK(report.getJson({"stages", "testgood.echo", "lines"}) == "3");
    fs::remove_all(out);

    // Plugin option errors are config errors like any other.
    CHECK_THROWS_WITH(Pipeline::fromString("plugins: [testgood]\nstages:\n"
                                           "  - stage: testgood.echo\n    repeats: 3\n",
                                           "cfg.yaml", "."),
                      Catch::Contains("cfg.yaml:4:5") && Catch::Contains("message, repeat, width_m"));
    ::unsetenv("VDBMAP_PLUGIN_PATH");
}

TEST_CASE("a plugin built against another ABI is rejected with file, expected, found", "[plugin]") {
    const std::string msg = loadError(pluginFile("badabi").string());
    CHECK(has(msg, pluginFile("badabi").filename().string()));
    CHECK(has(msg, "expected vdbmap plugin ABI " + std::to_string(VDBMAP_PLUGIN_ABI_VERSION)));
    CHECK(has(msg, "found 9999"));
    CHECK_FALSE(StageRegistry::instance().contains("badabi.anything"));
}

TEST_CASE("a text file named like a plugin is rejected without crashing", "[plugin]") {
    const std::string msg = loadError(pluginFile("textfile").string());
    CHECK(has(msg, "vdbmap_plugin_textfile.so"));
    CHECK(has(msg, "expected a shared object"));
    CHECK(has(msg, "found:"));
}

TEST_CASE("a shared object without the entry symbol is rejected", "[plugin]") {
    const std::string msg = loadError(pluginFile("nosymbol").string());
    CHECK(has(msg, "vdbmap_plugin_nosymbol.so"));
    CHECK(has(msg, "expected the entry symbol 'vdbmap_plugin_info_v1', found none"));
}

TEST_CASE("a plugin whose registration fails registers nothing", "[plugin]") {
    const std::string msg = loadError(pluginFile("badreg").string());
    CHECK(has(msg, "vdbmap_plugin_badreg.so"));
    CHECK(has(msg, "constructor failed on purpose"));
    CHECK_FALSE(StageRegistry::instance().contains("badreg.fine"));
    CHECK_FALSE(StageRegistry::instance().contains("badreg.throwing"));
}

TEST_CASE("missing plugins name what was searched", "[plugin]") {
    ::unsetenv("VDBMAP_PLUGIN_PATH");
    std::string msg = loadError("definitely_not_there");
    CHECK(has(msg, "plugin 'definitely_not_there' not found"));
    CHECK(has(msg, "vdbmap_plugin_definitely_not_there.so"));
    msg = loadError("/nonexistent/vdbmap_plugin_x.so");
    CHECK(has(msg, "/nonexistent/vdbmap_plugin_x.so: plugin file not found"));
    // In a config, the error also carries the file and line.
    CHECK_THROWS_WITH(Pipeline::fromString("plugins:\n  - definitely_not_there\nstages:\n"
                                           "  - stage: integrate.atsdf\n",
                                           "cfg.yaml", "."),
                      Catch::Contains("cfg.yaml:2:5"));
}
