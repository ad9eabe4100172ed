// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/Pipeline.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "pipeline/DatasetYaml.h"
#include "pipeline/Overrides.h"
#include "pipeline/PipelineImpl.h"
#include "pipeline/YamlOptions.h"
#include "vdbmap/Error.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/pipeline/StageRegistry.h"
#include "vdbmap/plugin/PluginLoader.h"

namespace vdbmap {
namespace fs = std::filesystem;

namespace {

nlohmann::json optionToJson(const OptionValue& value) {
    return std::visit([](const auto& v) { return nlohmann::json(v); }, value);
}

nlohmann::json specToJson(const OptionSpec& spec) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& info : spec.options()) out[info.key] = optionToJson(currentValue(info));
    return out;
}

/// The dataset section with every option; a rig's `cameras` as maps of every camera option.
nlohmann::json datasetToJson(const DatasetConfig& config, const OptionSpec& spec) {
    nlohmann::json out = specToJson(spec);
    if (config.rig.empty()) return out;
    out["cameras"] = nlohmann::json::array();
    for (const DatasetCameraConfig& camera : config.rig) {
        // declareOptions writes the defaults into the bound copy, so assign the values after.
        DatasetCameraConfig copy;
        OptionSpec camera_spec;
        copy.declareOptions(camera_spec);
        copy = camera;
        out["cameras"].push_back(specToJson(camera_spec));
    }
    return out;
}

}  // namespace

Pipeline::Pipeline() : impl_(std::make_unique<Impl>()) {}
Pipeline::~Pipeline() = default;

std::unique_ptr<Pipeline> Pipeline::fromFile(const fs::path& yaml_file,
                                             const std::vector<std::string>& overrides) {
    const std::string text = detail::readConfigFile(yaml_file);
    std::error_code ec;
    const fs::path base = fs::absolute(yaml_file, ec).parent_path();
    return fromString(text, yaml_file.string(), base, overrides);
}

namespace {

using detail::Override;

// Phase: plugins first, their stages must be registered before the stages are created.
void loadPlugins(const YAML::Node& plugins, Pipeline::Impl& p) {
    const std::string& src = p.source;
    if (!plugins.IsDefined() || plugins.IsNull()) return;
    if (!plugins.IsSequence()) {
        throw ConfigError(detail::yamlLocation(src, plugins) +
                          ": plugins: expected a list of plugin names or paths");
    }
    for (const auto& item : plugins) {
        if (!item.IsScalar()) {
            throw ConfigError(detail::yamlLocation(src, item) +
                              ": plugins: expected a plugin name or path");
        }
        try {
            p.plugin_specs.push_back(item.Scalar());
            p.plugin_files.push_back(PluginLoader::load(item.Scalar(), p.base_dir));
        } catch (const PluginError& e) {
            throw PluginError(detail::yamlLocation(src, item) + ": " + e.what());
        }
    }
}

// Phase: one stage instance per `- stage:` item, in order. Returns the stage names.
std::vector<std::string> createStages(const YAML::Node& stages, Pipeline::Impl& p) {
    const std::string& src = p.source;
    if (!stages.IsDefined() || stages.IsNull()) {
        throw ConfigError(src + ": missing required key 'stages' (an ordered list of "
                                "`- stage: <name>` items)");
    }
    if (!stages.IsSequence() || stages.size() == 0) {
        throw ConfigError(detail::yamlLocation(src, stages) +
                          ": stages: expected a non-empty list of `- stage: <name>` items");
    }
    std::vector<std::string> names;
    for (std::size_t i = 0; i < stages.size(); ++i) {
        const YAML::Node item = stages[i];
        const std::string where = detail::yamlLocation(src, item);
        const std::string index_label = "stages[" + std::to_string(i) + "]";
        if (!item.IsMap() || !item["stage"].IsDefined() || !item["stage"].IsScalar()) {
            throw ConfigError(where + ": " + index_label +
                              ": expected a map with key 'stage: <name>' and the stage's options");
        }
        const std::string name = item["stage"].Scalar();
        PipelineStage ps;
        try {
            ps.stage = StageRegistry::instance().create(name);
        } catch (const ConfigError& e) {
            throw ConfigError(where + ": " + index_label + ": " + e.what());
        }
        ps.where = where;
        ps.label = "stage '" + name + "' (" + index_label + ")";
        names.push_back(name);
        p.stages.push_back(std::move(ps));
    }
    return names;
}

// Phase: every stage's options from its YAML map and the overrides of its index.
void bindStageOptions(const YAML::Node& stages, const std::vector<Override>& overrides,
                      Pipeline::Impl& p) {
    for (std::size_t i = 0; i < p.stages.size(); ++i) {
        PipelineStage& ps = p.stages[i];
        ps.stage->declareOptions(ps.spec);
        auto entries = detail::yamlMapEntries(stages[i], p.source, ps.label, "stage");
        detail::applyOverrides(entries, overrides, Override::Target::StageIndex, i);
        detail::bindEntries(ps.spec, entries, ps.label, ps.where);
    }
}

// Binds one plain section (`output:`, `tiling:`) and its overrides. Returns where it is.
std::string bindSection(const YAML::Node& node, const std::string& section,
                        const std::vector<Override>& overrides, Override::Target target,
                        OptionSpec& spec, const std::string& src) {
    auto entries = detail::yamlMapEntries(node, src, section);
    detail::applyOverrides(entries, overrides, target);
    const std::string where = node.IsDefined() ? detail::yamlLocation(src, node) : src;
    detail::bindEntries(spec, entries, section, where);
    return where;
}

// Phase: the dataset, output and tiling sections.
void bindSections(const YAML::Node& root, const std::vector<Override>& overrides,
                  Pipeline::Impl& p) {
    p.dataset.declareOptions(p.dataset_spec);
    std::vector<detail::DatasetOverride> dataset_overrides;
    for (const auto& o : overrides) {
        if (o.target == Override::Target::Dataset) {
            dataset_overrides.push_back({o.key, o.value, o.text});
        }
    }
    p.has_dataset = detail::bindDatasetSection(root["dataset"], p.source, dataset_overrides,
                                               p.dataset, p.dataset_spec);
    p.output.declareOptions(p.output_spec);
    bindSection(root["output"], "output", overrides, Override::Target::Output, p.output_spec,
                p.source);
    p.tiling.declareOptions(p.tiling_spec);
    p.tiling_where = bindSection(root["tiling"], "tiling", overrides, Override::Target::Tiling,
                                 p.tiling_spec, p.source);
}

// Phase: each stage checks its values (ConfigError naming where it is) and declares layers.
void initializeStages(Pipeline::Impl& p) {
    for (auto& ps : p.stages) {
        try {
            ps.stage->initialize();
        } catch (const ConfigError& e) {
            throw ConfigError(ps.where + ": " + e.what());
        } catch (const Error& e) {
            throw ConfigError(ps.where + ": " + ps.label + ": " + e.what());
        }
        ps.stage->declareLayers(ps.layers);
    }
}

// The voxel size, when a stage before the tiled ones declares it (0 if none does; run()
// checks the map's).
double declaredVoxelSize(const Pipeline::Impl& p, std::size_t first_tiled) {
    double voxel_size_m = 0.0;
    for (std::size_t i = 0; i < std::min(p.stages.size(), first_tiled); ++i) {
        if (const OptionInfo* info = p.stages[i].spec.find("voxel_size_m")) {
            const OptionValue value = currentValue(*info);
            if (const double* v = std::get_if<double>(&value)) voxel_size_m = *v;
        }
    }
    return voxel_size_m;
}

}  // namespace

std::unique_ptr<Pipeline> Pipeline::fromString(const std::string& yaml_text,
                                               const std::string& source_name,
                                               const fs::path& base_dir,
                                               const std::vector<std::string>& override_texts) {
    registerBuiltinStages();
    std::unique_ptr<Pipeline> pipeline(new Pipeline());
    Impl& p = *pipeline->impl_;
    p.source = source_name;
    p.base_dir = base_dir;
    p.overrides = override_texts;
    std::vector<Override> overrides;
    for (const auto& text : override_texts) overrides.push_back(detail::parseOverride(text));

    const YAML::Node root = detail::parsePipelineRoot(yaml_text, p.source);
    loadPlugins(root["plugins"], p);
    const std::vector<std::string> names = createStages(root["stages"], p);
    detail::resolveStageNames(overrides, names);
    // Bind every section before any initialize() so that all key errors come first.
    bindStageOptions(root["stages"], overrides, p);
    bindSections(root, overrides, p);
    initializeStages(p);

    // Without an opened dataset, assume it provides every dataset layer; run() checks again
    // with what the dataset really has.
    std::vector<std::string> dataset_layers;
    if (p.has_dataset) dataset_layers = {layers::kScans, layers::kImages, layers::kSemanticImages};
    pipeline->checkLayers(dataset_layers);
    p.tiling.validate(declaredVoxelSize(p, pipeline->firstTiledStage()), p.tiling_where);
    return pipeline;
}

void Pipeline::checkLayers(const std::vector<std::string>& dataset_layers) const {
    const Impl& p = *impl_;
    std::set<std::string> available(dataset_layers.begin(), dataset_layers.end());
    for (std::size_t i = 0; i < p.stages.size(); ++i) {
        const PipelineStage& ps = p.stages[i];
        for (const auto& layer : ps.layers.readLayers()) {
            if (available.count(layer) > 0) continue;
            std::string later;
            for (std::size_t j = i + 1; j < p.stages.size(); ++j) {
                const auto& w = p.stages[j].layers.writtenLayers();
                if (std::find(w.begin(), w.end(), layer) != w.end()) {
                    later = "; " + p.stages[j].label + " writes it later: move that stage first";
                    break;
                }
            }
            std::string have;
            for (const auto& a : available) have += (have.empty() ? "" : ", ") + a;
            throw ConfigError(ps.where + ": " + ps.label + " reads layer '" + layer +
                              "', but no earlier stage writes it and the dataset does not "
                              "provide it (available before it: " +
                              (have.empty() ? std::string("none") : have) + ")" + later);
        }
        for (const auto& layer : ps.layers.writtenLayers()) available.insert(layer);
    }
}

const std::string& Pipeline::source() const { return impl_->source; }
const fs::path& Pipeline::baseDir() const { return impl_->base_dir; }
std::size_t Pipeline::numStages() const { return impl_->stages.size(); }
const Stage& Pipeline::stage(std::size_t i) const { return *impl_->stages.at(i).stage; }
std::vector<std::string> Pipeline::stageNames() const {
    std::vector<std::string> names;
    for (const auto& ps : impl_->stages) names.emplace_back(ps.stage->name());
    return names;
}
bool Pipeline::hasDataset() const { return impl_->has_dataset; }
const DatasetConfig& Pipeline::datasetConfig() const { return impl_->dataset; }
const OutputConfig& Pipeline::outputConfig() const { return impl_->output; }
const TilingConfig& Pipeline::tilingConfig() const { return impl_->tiling; }

std::size_t Pipeline::firstTiledStage() const {
    const Impl& p = *impl_;
    for (std::size_t i = 0; i < p.stages.size(); ++i) {
        const LayerSpec& l = p.stages[i].layers;
        auto has = [](const std::vector<std::string>& v) {
            return std::find(v.begin(), v.end(), std::string(layers::kMesh)) != v.end();
        };
        if (has(l.readLayers()) || has(l.writtenLayers())) return i;
    }
    return p.stages.size();
}
const std::vector<fs::path>& Pipeline::pluginFiles() const { return impl_->plugin_files; }

std::string Pipeline::resolvedConfigJson() const {
    const Impl& p = *impl_;
    nlohmann::json config;
    config["source"] = p.source;
    config["dataset"] =
        p.has_dataset ? datasetToJson(p.dataset, p.dataset_spec) : nlohmann::json(nullptr);
    nlohmann::json plugins = nlohmann::json::array();
    for (std::size_t i = 0; i < p.plugin_specs.size(); ++i) {
        plugins.push_back({{"name", p.plugin_specs[i]}, {"file", p.plugin_files[i].string()}});
    }
    config["plugins"] = plugins;
    nlohmann::json stages = nlohmann::json::array();
    for (const auto& ps : p.stages) {
        stages.push_back({{"stage", std::string(ps.stage->name())},
                          {"options", specToJson(ps.spec)}});
    }
    config["stages"] = stages;
    config["output"] = specToJson(p.output_spec);
    config["tiling"] = specToJson(p.tiling_spec);
    config["overrides"] = p.overrides;
    return config.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void OutputConfig::declareOptions(OptionSpec& spec) {
    spec.add("dir", "Output folder when `vdbmap run` has no -o (relative to the current folder)",
             dir, std::string("out"));
    spec.add("write_map", "Write map.vdb when a stage created a map", write_map, true);
    spec.add("write_mesh", "Write mesh.ply when a stage created a mesh", write_mesh, true);
    spec.add("write_report", "Write report.json (also when a stage fails)", write_report, true);
}

int exitCodeFor(const std::exception& error) {
    if (dynamic_cast<const ConfigError*>(&error) != nullptr) return 2;
    if (dynamic_cast<const PluginError*>(&error) != nullptr) return 2;
    return 1;
}

}  // namespace vdbmap
