// SPDX-License-Identifier: Apache-2.0
// `--set key.path=value` overrides of a pipeline file: parsed, resolved to their section or
// stage, and applied to a section's entries before binding.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "pipeline/YamlOptions.h"

namespace vdbmap::detail {

/// One `--set path=value`, split into its target section and key.
struct Override {
    enum class Target { Dataset, Output, Tiling, StageIndex, StageName } target;
    std::size_t index = 0;   ///< for StageIndex (after resolving StageName too)
    std::string remainder;   ///< "integrate.atsdf.voxel_size_m" before the stage name is known
    std::string key;
    YAML::Node value;
    std::string text;        ///< the original "path=value"
};

/// Parses "path=value" (the value as YAML). Throws ConfigError naming the text.
Override parseOverride(const std::string& text);

/// Replaces or appends the override's entry among a section's entries.
void applyOverride(std::vector<YamlEntry>& entries, const Override& o);

/// Applies every override of `target` (and, for StageIndex, of stage `index`) to `entries`.
void applyOverrides(std::vector<YamlEntry>& entries, const std::vector<Override>& overrides,
                    Override::Target target, std::size_t index = 0);

/// Turns `<stage name>.<key>` overrides into stage indices; the name must appear once among
/// `names`, and every stage index must be below names.size(). Throws ConfigError.
void resolveStageNames(std::vector<Override>& overrides, const std::vector<std::string>& names);

}  // namespace vdbmap::detail
