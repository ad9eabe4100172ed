// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <regex>

#include "support/BuiltPlugins.h"
#include "support/TestStages.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/StageRegistry.h"
#include "vdbmap/plugin/PluginLoader.h"

using namespace vdbmap;

TEST_CASE("built-in stages are registered", "[registry]") {
    registerBuiltinStages();
    registerBuiltinStages();  // idempotent
    auto& registry = StageRegistry::instance();
    CHECK(registry.contains("integrate.atsdf"));
    CHECK(registry.contains("mesh.marching_cubes"));
}

TEST_CASE("every registered stage can be created and documents every option", "[registry]") {
    registerBuiltinStages();
    // The in-tree plugins too: every one this build has must load.
    for (const std::string& name : test::builtPlugins()) {
        INFO("plugin " << name);
        REQUIRE_NOTHROW(PluginLoader::load(name));
    }
    const auto& registry = StageRegistry::instance();
    if (test::isBuiltPlugin("texture")) CHECK(registry.contains("texture.mrf"));
    if (test::isBuiltPlugin("semantic")) CHECK(registry.contains("semantic.mrf"));
    if (test::isBuiltPlugin("tiles3d")) CHECK(registry.contains("export.3dtiles"));
    if (test::isBuiltPlugin("cgal")) CHECK(registry.contains("mesh.simplify"));
    // A plugin the build leaves out fails with "not found", naming it.
    for (const std::string& name : test::inTreePlugins()) {
        if (!test::isBuiltPlugin(name)) {
            CHECK_THROWS_WITH(PluginLoader::load(name), Catch::Contains("'" + name + "' not found"));
        }
    }
    const std::regex stage_name("[a-z0-9_]+\\.[a-z0-9_.]+");
    const std::regex key_name("[a-zA-Z][a-zA-Z0-9_]*");
    const auto entries = StageRegistry::instance().entries();
    REQUIRE_FALSE(entries.empty());
    for (std::size_t i = 1; i < entries.size(); ++i) CHECK(entries[i - 1].name < entries[i].name);
    for (const auto& entry : entries) {
        INFO("stage " << entry.name);
        CHECK(std::regex_match(entry.name, stage_name));
        auto stage = StageRegistry::instance().create(entry.name);
        REQUIRE(stage);
        CHECK(std::string(stage->name()) == entry.name);
        OptionSpec spec;
        stage->declareOptions(spec);
        for (const auto& option : spec.options()) {
            INFO("option " << option.key);
            CHECK(std::regex_match(option.key, key_name));
            CHECK_FALSE(option.doc.empty());
        }
    }
}

TEST_CASE("registry rejects duplicates and unknown names", "[registry]") {
    test::registerTestStages();
    auto& registry = StageRegistry::instance();
    CHECK_THROWS_WITH(registry.add<test::RecorderStage>("again"),
                      Catch::Contains("already registered by test"));
    CHECK_THROWS_AS(registry.add("", "x", [] { return std::unique_ptr<Stage>(); }), InvalidInput);
    CHECK_THROWS_AS(registry.add("test.nofactory", "x", StageFactory{}), InvalidInput);
    try {
        registry.create("nope.stage");
        FAIL("no exception");
    } catch (const ConfigError& e) {
        CHECK(std::string(e.what()).find("unknown stage 'nope.stage'") != std::string::npos);
        CHECK(std::string(e.what()).find("test.recorder") != std::string::npos);
    }
    registry.add("test.nullfactory", "x", [] { return std::unique_ptr<Stage>(); });
    CHECK_THROWS_AS(registry.create("test.nullfactory"), Error);
}
