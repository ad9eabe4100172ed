// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "Commands.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/StageRegistry.h"
#include "vdbmap/plugin/PluginLoader.h"

namespace {

struct DescribeArgs {
    std::string what;
    std::vector<std::string> plugins;
};

std::string pad(const std::string& s, std::size_t width) {
    return s.size() >= width ? s + " " : s + std::string(width - s.size(), ' ');
}

/// Prints one option per line: key, type, default, unit, doc.
void printSpec(const vdbmap::OptionSpec& spec) {
    if (spec.options().empty()) {
        std::cout << "    (no options)\n";
        return;
    }
    std::size_t key_w = 3, type_w = 4, def_w = 7;
    std::vector<std::string> defaults;
    for (const auto& o : spec.options()) {
        defaults.push_back(o.required ? "(required)" : vdbmap::formatOptionValue(o.default_value));
        key_w = std::max(key_w, o.key.size());
        type_w = std::max(type_w, std::string(vdbmap::optionTypeName(o.type)).size());
        def_w = std::max(def_w, std::min<std::size_t>(defaults.back().size(), 24));
    }
    std::cout << "    " << pad("key", key_w + 2) << pad("type", type_w + 2)
              << pad("default", def_w + 2) << pad("unit", 6) << "description\n";
    for (std::size_t i = 0; i < spec.options().size(); ++i) {
        const auto& o = spec.options()[i];
        std::cout << "    " << pad(o.key, key_w + 2) << pad(vdbmap::optionTypeName(o.type), type_w + 2)
                  << pad(defaults[i], def_w + 2) << pad(o.unit.empty() ? "-" : o.unit, 6) << o.doc
                  << "\n";
    }
}

void printStage(const vdbmap::StageRegistry::Entry& entry) {
    std::unique_ptr<vdbmap::Stage> stage = entry.factory();
    vdbmap::OptionSpec spec;
    stage->declareOptions(spec);
    std::cout << entry.name << "  [" << entry.origin << "]\n";
    if (!entry.summary.empty()) std::cout << "  " << entry.summary << "\n";
    printSpec(spec);
    std::cout << "\n";
}

/// Loads the plugins named with --plugin, else every plugin found on the search path (a
/// plugin that fails to load is reported and skipped).
void loadPlugins(const std::vector<std::string>& explicit_plugins) {
    for (const auto& p : explicit_plugins) vdbmap::PluginLoader::load(p);
    if (!explicit_plugins.empty()) return;
    for (const auto& name : vdbmap::PluginLoader::discover()) {
        try {
            vdbmap::PluginLoader::load(name);
        } catch (const vdbmap::PluginError& e) {
            vdbmap::logWarn(std::string("skipping plugin: ") + e.what());
        }
    }
}

int describe(const DescribeArgs& args) {
    if (args.what == "dataset") {
        vdbmap::DatasetConfig config;
        vdbmap::OptionSpec spec;
        config.declareOptions(spec);
        std::cout << "dataset  [pipeline section `dataset:`]\n"
                  << "  Where the scans, poses, calibration and images come from (docs/DATA.md)\n";
        printSpec(spec);
        vdbmap::DatasetCameraConfig camera;
        vdbmap::OptionSpec camera_spec;
        camera.declareOptions(camera_spec);
        std::cout
            << "\n  cameras (generic layout): a list of camera maps, one per camera of a rig, "
               "instead of the\n  single-camera keys image_dir ... calib_file; each map "
               "takes these keys (paths relative to `path`):\n";
        printSpec(camera_spec);
        std::cout << "  e.g.\n"
                  << "    cameras:\n"
                  << "      - {name: front, image_dir: image_front, semantic_dir: semantic_front,\n"
                  << "         intrinsics: [537, 537, 639.5, 359.5], T_C_L: [12 numbers]}\n"
                  << "      - {image_dir: image_rear, calib_file: calib_rear.txt}\n";
        return 0;
    }
    if (args.what == "output") {
        vdbmap::OutputConfig config;
        vdbmap::OptionSpec spec;
        config.declareOptions(spec);
        std::cout << "output  [pipeline section `output:`]\n"
                  << "  What `vdbmap run` writes besides the stages' own files\n";
        printSpec(spec);
        return 0;
    }
    if (args.what == "tiling") {
        vdbmap::TilingConfig config;
        vdbmap::OptionSpec spec;
        config.declareOptions(spec);
        std::cout << "tiling  [pipeline section `tiling:`]\n"
                  << "  Square ground tiles: the stages from the first one that reads or writes the\n"
                  << "  mesh run once per tile, on its mesh plus a halo, into tiles/<ix>_<iy>/;\n"
                  << "  tiles.json indexes them (docs/tiling.md). A tile smaller than one voxel\n"
                  << "  leaf (8 voxels) or a negative halo is a config error.\n";
        printSpec(spec);
        std::cout << "  e.g.\n    tiling: {tile_size_m: 64, halo_m: 4, max_view_distance_m: 40}\n";
        return 0;
    }
    loadPlugins(args.plugins);
    const auto entries = vdbmap::StageRegistry::instance().entries();
    if (!args.what.empty()) {
        for (const auto& entry : entries) {
            if (entry.name == args.what) {
                printStage(entry);
                return 0;
            }
        }
        // Gives the ConfigError with the list of registered stages.
        vdbmap::StageRegistry::instance().create(args.what);
        return 2;
    }
    std::cout << "Pipeline sections: dataset, output, tiling (see `vdbmap describe dataset`).\n"
              << "Registered stages (" << entries.size() << "):\n\n";
    for (const auto& entry : entries) printStage(entry);
    return 0;
}

}  // namespace

void addDescribeCommand(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<DescribeArgs>();
    CLI::App* cmd = app.add_subcommand(
        "describe", "List the stages and every option (key, type, default, unit, doc)");
    cmd->add_option("what", args->what, "A stage name, or `dataset` / `output` / `tiling` for those sections");
    cmd->add_option("--plugin", args->plugins,
                    "Load these plugins (name or path) instead of every plugin found")
        ->allow_extra_args(false);
    cmd->callback([args, &exit_code] { exit_code = describe(*args); });
}
