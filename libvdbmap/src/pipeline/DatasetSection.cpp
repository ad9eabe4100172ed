// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/DatasetSection.h"

#include <yaml-cpp/yaml.h>

#include "pipeline/DatasetYaml.h"
#include "pipeline/YamlOptions.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/OptionSpec.h"

namespace vdbmap {
namespace fs = std::filesystem;

DatasetSection loadDatasetSection(const fs::path& yaml_file,
                                  const std::vector<std::string>& overrides) {
    const std::string src = yaml_file.string();
    const YAML::Node root = detail::parsePipelineRoot(detail::readConfigFile(yaml_file), src);
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
    std::error_code ec;
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
