// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/DatasetSection.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

#include "pipeline/DatasetYaml.h"
#include "vdbmap/Error.h"
#include "vdbmap/pipeline/OptionSpec.h"

namespace vdbmap {
namespace fs = std::filesystem;

DatasetSection loadDatasetSection(const fs::path& yaml_file,
                                  const std::vector<std::string>& overrides) {
    const std::string src = yaml_file.string();
    std::error_code ec;
    if (!fs::is_regular_file(yaml_file, ec)) throw ConfigError(src + ": config file not found");
    std::ifstream in(yaml_file, std::ios::binary);
    if (!in) throw ConfigError(src + ": cannot open config file");
    std::ostringstream text;
    text << in.rdbuf();
    YAML::Node root;
    try {
        root = YAML::Load(text.str());
    } catch (const YAML::ParserException& e) {
        throw ConfigError(src + ":" + std::to_string(e.mark.line + 1) + ":" +
                          std::to_string(e.mark.column + 1) + ": YAML syntax error: " + e.msg);
    } catch (const YAML::Exception& e) {
        throw ConfigError(src + ": YAML error: " + e.what());
    }
    if (!root.IsMap()) {
        throw ConfigError(detail::yamlLocation(src, root) + ": expected a map with key 'dataset'");
    }
    for (const auto& item : root) {
        const std::string key = item.first.Scalar();
        if (key != "dataset" && key != "plugins" && key != "stages" && key != "output") {
            throw ConfigError(detail::yamlLocation(src, item.first) + ": unknown top-level key '" +
                              key + "'; valid keys: dataset, plugins, stages, output");
        }
    }
    std::vector<detail::DatasetOverride> dataset_overrides;
    for (const std::string& o : overrides) {
        const std::size_t eq = o.find('=');
        const std::string prefix = "dataset.";
        if (eq == std::string::npos || o.rfind(prefix, 0) != 0 || eq <= prefix.size()) {
            throw ConfigError("--set '" + o + "': expected dataset.<key>=value");
        }
        dataset_overrides.push_back({o.substr(prefix.size(), eq - prefix.size()),
                                     detail::parseOverrideValue(o.substr(eq + 1)), o});
    }
    DatasetSection section;
    section.base_dir = fs::absolute(yaml_file, ec).parent_path();
    OptionSpec spec;
    section.config.declareOptions(spec);
    if (!detail::bindDatasetSection(root["dataset"], src, dataset_overrides, section.config,
                                    spec)) {
        throw ConfigError(src + ": no 'dataset:' section");
    }
    return section;
}

}  // namespace vdbmap
