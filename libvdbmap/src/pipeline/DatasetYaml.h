// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "pipeline/YamlOptions.h"
#include "vdbmap/io/Dataset.h"

namespace vdbmap::detail {

/// One `--set dataset.<key>=value` override: the key after "dataset.", the value parsed as
/// YAML, and the original text for messages.
struct DatasetOverride {
    std::string key;
    YAML::Node value;
    std::string text;
};

/// The value of a `--set path=value` override, parsed as YAML (a plain string if it is not
/// valid YAML).
YAML::Node parseOverrideValue(const std::string& value);

/// Binds the `dataset:` node of `source` (null / undefined = no section) and the overrides
/// into `config` through `spec` (DatasetConfig::declareOptions must already be declared on
/// `spec`). A `cameras` value that is a list of maps fills config.rig: each map is bound with
/// DatasetCameraConfig::declareOptions, with the same checks and messages as a section
/// ("file:line:col: dataset: cameras[1]: unknown key 'fx'; valid keys: ..."); a list of
/// scalars is the KITTI folder list; a list mixing both is a ConfigError. A relative `path`
/// given by an override is made absolute against the current folder. Returns whether there is
/// a dataset section (in the file or from an override). Throws ConfigError.
bool bindDatasetSection(const YAML::Node& dataset, const std::string& source,
                        const std::vector<DatasetOverride>& overrides, DatasetConfig& config,
                        OptionSpec& spec);

}  // namespace vdbmap::detail
