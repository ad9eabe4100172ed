// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/io/Dataset.h"

namespace vdbmap {

/// The `dataset:` section of a YAML file, and the folder its relative paths resolve against.
struct DatasetSection {
    DatasetConfig config;
    std::filesystem::path base_dir;  ///< the YAML file's folder (absolute)
};

/// Reads only the `dataset:` section of `yaml_file`: a pipeline (its plugins and stages are
/// not loaded) or a file holding just `dataset:` (as vdbmap-sim writes next to a generic
/// sequence). The section gets the same checks as in `vdbmap run` (unknown keys with
/// file:line:col and the valid keys, wrong types, the `cameras:` list of maps), so a dataset
/// opened from it is the one a run of that file reads. `overrides` are `dataset.<key>=value`
/// (as `vdbmap run --set`; a relative `path` given this way is relative to the current folder).
/// Throws ConfigError for a missing or unreadable file, a YAML syntax error, an unknown
/// top-level key, an override outside `dataset.`, a bad key or value, or no dataset section.
DatasetSection loadDatasetSection(const std::filesystem::path& yaml_file,
                                  const std::vector<std::string>& overrides = {});

}  // namespace vdbmap
