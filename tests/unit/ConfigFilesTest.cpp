// SPDX-License-Identifier: Apache-2.0
// Every example pipeline in config/ loads and passes every check (keys, types, plugins,
// layers) without running. A config may be skipped only when it needs an in-tree plugin that
// this build leaves out (e.g. VDBMAP_BUILD_PLUGINS=OFF); with the plugins built, every config
// must validate.
#include <catch2/catch.hpp>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/BuiltPlugins.h"
#include "vdbmap/Error.h"
#include "vdbmap/pipeline/Pipeline.h"

using namespace vdbmap;
namespace fs = std::filesystem;

namespace {

/// The names in the config's `plugins:` list.
std::vector<std::string> configPlugins(const fs::path& file) {
    std::vector<std::string> names;
    const YAML::Node plugins = YAML::LoadFile(file.string())["plugins"];
    if (plugins && plugins.IsSequence()) {
        for (const auto& p : plugins) names.push_back(p.as<std::string>());
    }
    return names;
}

}  // namespace

TEST_CASE("every config/ file validates", "[yaml][config]") {
    const fs::path dir = fs::path(VDBMAP_SOURCE_DIR) / "config";
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() == ".yaml") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    REQUIRE(files.size() >= 3);
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
