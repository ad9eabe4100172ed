// SPDX-License-Identifier: Apache-2.0
// Every pipeline in config/ (the examples) and config/experiments/ (the experiments' base files)
// loads and passes every check (keys, types, plugins, layers) without running. A config may be
// skipped only when it needs an in-tree plugin that this build leaves out (e.g.
// VDBMAP_BUILD_PLUGINS=OFF); with the plugins built, every config must validate. Each file's
// header names the command that runs it, and config/README.md lists every file.
#include <catch2/catch.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/BuiltPlugins.h"
#include "vdbmap/Error.h"
#include "vdbmap/pipeline/Pipeline.h"

using namespace vdbmap;
namespace fs = std::filesystem;

namespace {

const fs::path kConfigDir = fs::path(VDBMAP_SOURCE_DIR) / "config";

/// The .yaml files of config/ and config/experiments/, sorted.
std::vector<fs::path> configFiles() {
    std::vector<fs::path> files;
    for (const fs::path& dir : {kConfigDir, kConfigDir / "experiments"}) {
        for (const auto& entry : fs::directory_iterator(dir)) {
            if (entry.path().extension() == ".yaml") files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// The path of `file` relative to config/, with '/' separators ("experiments/suv.yaml").
std::string relativeName(const fs::path& file) {
    return fs::relative(file, kConfigDir).generic_string();
}

/// The names in the config's `plugins:` list.
std::vector<std::string> configPlugins(const fs::path& file) {
    std::vector<std::string> names;
    const YAML::Node plugins = YAML::LoadFile(file.string())["plugins"];
    if (plugins && plugins.IsSequence()) {
        for (const auto& p : plugins) names.push_back(p.as<std::string>());
    }
    return names;
}

/// The comment lines before the first YAML key, without their leading '#'.
std::string headerComment(const fs::path& file) {
    std::ifstream in(file);
    std::string line, header;
    while (std::getline(in, line) && !line.empty() && line[0] == '#') header += line.substr(1) + "\n";
    return header;
}

std::string readText(const fs::path& file) {
    std::ifstream in(file);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace

TEST_CASE("every config/ and config/experiments/ file validates", "[yaml][config]") {
    const std::vector<fs::path> files = configFiles();
    REQUIRE(files.size() >= 10);
    std::size_t validated = 0, skipped = 0;
    for (const auto& file : files) {
        INFO("config " << file.string());
        std::string missing;  // the first one: the pipeline loads its plugins in order
        for (const auto& plugin : configPlugins(file)) {
            if (!test::isBuiltPlugin(plugin)) {
                missing = plugin;
                break;
            }
        }
        if (missing.empty()) {
            // Every plugin it needs is built: any error fails the test.
            try {
                auto pipeline = Pipeline::fromFile(file);
                CHECK(pipeline->numStages() > 0);
                CHECK(pipeline->hasDataset());
                ++validated;
            } catch (const std::exception& e) {
                FAIL_CHECK("does not validate: " << e.what());
            }
            continue;
        }
        // The plugin is not part of this build: the config must fail on exactly that.
        INFO("plugin '" << missing << "' is not built");
        CHECK_THROWS_WITH(Pipeline::fromFile(file), Catch::Contains("'" + missing + "' not found"));
        ++skipped;
    }
    CHECK(validated + skipped == files.size());
    if (test::isBuiltPlugin("texture") && test::isBuiltPlugin("semantic")) {
        CHECK(skipped == 0);
        CHECK(validated == files.size());
    }
}

TEST_CASE("every config file says in its header how to run it", "[config]") {
    for (const auto& file : configFiles()) {
        const std::string name = relativeName(file);
        INFO("config/" << name << ", header:\n" << headerComment(file));
        CHECK_THAT(headerComment(file), Catch::Contains("vdbmap run config/" + name));
    }
}

TEST_CASE("config/README.md lists every config file", "[config]") {
    const std::string readme = readText(kConfigDir / "README.md");
    REQUIRE_FALSE(readme.empty());
    for (const auto& file : configFiles()) {
        const std::string name = relativeName(file);
        INFO("config/" << name);
        CHECK_THAT(readme, Catch::Contains("(" + name + ")"));
    }
}
