// SPDX-License-Identifier: Apache-2.0
// The `dataset:` section of a YAML file, with the generic layout's `cameras:` list of maps.
#include "pipeline/DatasetYaml.h"

#include <filesystem>

#include "vdbmap/Error.h"
#include "vdbmap/core/OptionSpec.h"

namespace vdbmap::detail {
namespace {

bool isFromOverride(const YamlEntry& entry) { return entry.where.rfind("--set ", 0) == 0; }

/// Binds a `cameras:` list of maps into `rig`. Positions inside an override's value are
/// relative to the override text, so those entries are located by the override itself.
void bindCameraMaps(const YamlEntry& entry, const std::string& source,
                    std::vector<DatasetCameraConfig>& rig) {
    rig.clear();
    const bool from_override = isFromOverride(entry);
    for (std::size_t c = 0; c < entry.value.size(); ++c) {
        const YAML::Node item = entry.value[c];
        const std::string label = "dataset: cameras[" + std::to_string(c) + "]";
        const std::string item_where = from_override ? entry.where : yamlLocation(source, item);
        std::vector<YamlEntry> fields = yamlMapEntries(item, source, label);
        if (from_override) {
            for (auto& field : fields) field.where = entry.where;
        }
        rig.emplace_back();
        OptionSpec spec;
        rig.back().declareOptions(spec);
        bindEntries(spec, fields, label, item_where);
    }
}

}  // namespace

YAML::Node parseOverrideValue(const std::string& value) {
    try {
        return YAML::Load(value);
    } catch (const YAML::Exception&) {
        return YAML::Node(value);
    }
}

bool bindDatasetSection(const YAML::Node& dataset, const std::string& source,
                        const std::vector<DatasetOverride>& overrides, DatasetConfig& config,
                        OptionSpec& spec) {
    std::vector<YamlEntry> entries = yamlMapEntries(dataset, source, "dataset");
    bool has_dataset = dataset.IsDefined() && !dataset.IsNull();
    bool path_overridden = false;
    for (const auto& o : overrides) {
        const std::string where = "--set " + o.text;
        bool replaced = false;
        for (auto& entry : entries) {
            if (entry.key == o.key) {
                entry.value = o.value;
                entry.where = where;
                replaced = true;
                break;
            }
        }
        if (!replaced) entries.push_back({o.key, o.value, where});
        has_dataset = true;
        path_overridden = path_overridden || o.key == "path";
    }
    if (!has_dataset) return false;

    // `cameras` is a list of folder names (KITTI) or of camera maps (generic): the maps go to
    // config.rig, everything else through the section's own spec.
    std::vector<YamlEntry> plain;
    const YamlEntry* camera_maps = nullptr;
    for (const auto& entry : entries) {
        if (entry.key == "cameras" && entry.value.IsSequence()) {
            std::size_t maps = 0;
            for (std::size_t i = 0; i < entry.value.size(); ++i) {
                maps += entry.value[i].IsMap() ? 1 : 0;
            }
            if (maps > 0 && maps < entry.value.size()) {
                throw ConfigError(entry.where +
                                  ": dataset: key 'cameras': expected a list of folder names "
                                  "(KITTI) or a list of camera maps (generic), found a list "
                                  "mixing both");
            }
            if (maps > 0) {
                camera_maps = &entry;
                continue;
            }
        }
        plain.push_back(entry);
    }
    bindEntries(spec, plain, "dataset",
                dataset.IsDefined() ? yamlLocation(source, dataset) : source);
    if (camera_maps != nullptr) bindCameraMaps(*camera_maps, source, config.rig);
    if (path_overridden && !config.path.empty() &&
        std::filesystem::path(config.path).is_relative()) {
        config.path = std::filesystem::absolute(config.path).string();
    }
    return true;
}

}  // namespace vdbmap::detail
