// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/core/OptionSpec.h"

namespace vdbmap::detail {

/// One key/value of a config section, with where it came from: "file:line:col" for the YAML
/// file, "--set path=value" for an override.
struct YamlEntry {
    std::string key;
    YAML::Node value;
    std::string where;
};

/// The text of a pipeline file. Throws ConfigError "<file>: config file not found" or
/// "<file>: cannot open config file".
std::string readConfigFile(const std::filesystem::path& file);

/// Parses the text of a pipeline file (`source` names it in messages): a map whose keys are
/// among dataset, plugins, stages, output. Throws ConfigError with file:line:col on a YAML
/// syntax error, a root that is not a map or an unknown top-level key.
YAML::Node parsePipelineRoot(const std::string& text, const std::string& source);

/// "file:line:col" of a node (1-based), or just "file" when the node has no position.
std::string yamlLocation(const std::string& source, const YAML::Node& node);

/// The entries of a YAML map, in file order, skipping `skip_key`. Throws ConfigError if `map`
/// is neither a map nor null, or a key is not a scalar.
std::vector<YamlEntry> yamlMapEntries(const YAML::Node& map, const std::string& source,
                                      const std::string& what, const std::string& skip_key = "");

/// Converts a YAML value to an option of type `want` (type-directed: any scalar is a valid
/// string; "5" is a valid double; null is an empty string or list). Throws ConfigError
/// "expected <type>, found <kind> <text>" (no location: the caller adds it).
OptionValue yamlToOption(const YAML::Node& node, OptionType want);

/// Binds entries into `spec`: unknown keys (with the valid keys), wrong types and missing
/// required keys throw ConfigError prefixed with the entry's location and `label` (e.g.
/// "stage 'integrate.atsdf' (stages[0])"). `section_where` locates the section for a
/// missing key.
void bindEntries(OptionSpec& spec, const std::vector<YamlEntry>& entries, const std::string& label,
                 const std::string& section_where);

}  // namespace vdbmap::detail
