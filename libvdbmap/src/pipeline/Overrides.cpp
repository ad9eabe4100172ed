// SPDX-License-Identifier: Apache-2.0
#include "pipeline/Overrides.h"

#include "pipeline/DatasetYaml.h"

#include <algorithm>

#include "vdbmap/Error.h"

namespace vdbmap::detail {

Override parseOverride(const std::string& text) {
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) {
        throw ConfigError("--set '" + text + "': expected key.path=value");
    }
    Override o;
    o.text = text;
    const std::string path = text.substr(0, eq);
    const std::string value = text.substr(eq + 1);
    o.value = parseOverrideValue(value);
    auto startsWith = [&](const std::string& prefix) { return path.rfind(prefix, 0) == 0; };
    if (startsWith("dataset.")) {
        o.target = Override::Target::Dataset;
        o.key = path.substr(8);
    } else if (startsWith("output.")) {
        o.target = Override::Target::Output;
        o.key = path.substr(7);
    } else if (startsWith("tiling.")) {
        o.target = Override::Target::Tiling;
        o.key = path.substr(7);
    } else if (startsWith("stages.")) {
        const std::string rest = path.substr(7);
        const std::size_t dot = rest.find('.');
        const std::string index = rest.substr(0, dot);
        if (dot == std::string::npos || index.empty() || index.size() > 9 ||
            !std::all_of(index.begin(), index.end(), ::isdigit)) {
            throw ConfigError("--set '" + text + "': expected stages.<index>.<key>=value");
        }
        o.target = Override::Target::StageIndex;
        o.index = std::stoul(index);
        o.key = rest.substr(dot + 1);
    } else {
        o.target = Override::Target::StageName;
        o.remainder = path;
    }
    if (o.target != Override::Target::StageName && o.key.empty()) {
        throw ConfigError("--set '" + text + "': the key after the last '.' is empty");
    }
    return o;
}

void applyOverride(std::vector<YamlEntry>& entries, const Override& o) {
    const std::string where = "--set " + o.text;
    for (auto& entry : entries) {
        if (entry.key == o.key) {
            entry.value = o.value;
            entry.where = where;
            return;
        }
    }
    entries.push_back({o.key, o.value, where});
}

void resolveStageNames(std::vector<Override>& overrides, const std::vector<std::string>& names) {
    for (auto& o : overrides) {
        if (o.target != Override::Target::StageName) continue;
        std::string best;
        for (const auto& name : names) {
            if (o.remainder.rfind(name + ".", 0) == 0 && name.size() > best.size()) best = name;
        }
        if (best.empty()) {
            std::string list;
            for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
            throw ConfigError("--set '" + o.text +
                              "': unknown path; use dataset.<key>, output.<key>, tiling.<key>, "
                              "stages.<index>.<key> or <stage>.<key> with a stage of this "
                              "pipeline (" + list + ")");
        }
        const auto count = std::count(names.begin(), names.end(), best);
        if (count > 1) {
            throw ConfigError("--set '" + o.text + "': stage '" + best + "' appears " +
                              std::to_string(count) + " times; use stages.<index>.<key>");
        }
        o.index = static_cast<std::size_t>(std::find(names.begin(), names.end(), best) -
                                           names.begin());
        o.key = o.remainder.substr(best.size() + 1);
        o.target = Override::Target::StageIndex;
        if (o.key.empty()) throw ConfigError("--set '" + o.text + "': empty key");
    }
    for (const auto& o : overrides) {
        if (o.target == Override::Target::StageIndex && o.index >= names.size()) {
            throw ConfigError("--set '" + o.text + "': stage index " + std::to_string(o.index) +
                              " out of range; the pipeline has " + std::to_string(names.size()) +
                              " stages");
        }
    }
}

void applyOverrides(std::vector<YamlEntry>& entries, const std::vector<Override>& overrides,
                    Override::Target target, std::size_t index) {
    for (const auto& o : overrides) {
        if (o.target == target && (target != Override::Target::StageIndex || o.index == index)) {
            applyOverride(entries, o);
        }
    }
}

}  // namespace vdbmap::detail
