// SPDX-License-Identifier: Apache-2.0
#include "pipeline/YamlOptions.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <limits>
#include <fstream>
#include <set>
#include <sstream>

#include "vdbmap/Error.h"

namespace vdbmap::detail {

std::string readConfigFile(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
        throw ConfigError(file.string() + ": config file not found");
    }
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ConfigError(file.string() + ": cannot open config file");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

YAML::Node parsePipelineRoot(const std::string& text, const std::string& source) {
    static const std::vector<std::string> kTopLevelKeys{"dataset", "plugins", "stages", "output",
                                                        "tiling"};
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
        throw ConfigError(source + ":" + std::to_string(e.mark.line + 1) + ":" +
                          std::to_string(e.mark.column + 1) + ": YAML syntax error: " + e.msg);
    } catch (const YAML::Exception& e) {
        throw ConfigError(source + ": YAML error: " + e.what());
    }
    if (!root.IsMap()) {
        throw ConfigError(yamlLocation(source, root) +
                          ": expected a map with keys dataset, plugins, stages, output");
    }
    for (const auto& item : root) {
        const std::string key = item.first.Scalar();
        if (std::find(kTopLevelKeys.begin(), kTopLevelKeys.end(), key) == kTopLevelKeys.end()) {
            throw ConfigError(yamlLocation(source, item.first) + ": unknown top-level key '" + key +
                              "'; valid keys: dataset, plugins, stages, output, tiling");
        }
    }
    return root;
}

namespace {

bool isQuoted(const YAML::Node& node) { return node.Tag() == "!"; }

bool parseInt(const std::string& text, std::int64_t& out) {
    if (text.empty()) return false;
    std::size_t start = (text[0] == '-' || text[0] == '+') ? 1 : 0;
    if (start == text.size()) return false;
    for (std::size_t i = start; i < text.size(); ++i) {
        if (text[i] < '0' || text[i] > '9') return false;
    }
    errno = 0;
    long long v = std::strtoll(text.c_str(), nullptr, 10);
    if (errno == ERANGE) return false;
    out = v;
    return true;
}

bool parseDouble(const std::string& text, double& out) {
    if (text == ".inf" || text == "+.inf" || text == ".Inf") {
        out = std::numeric_limits<double>::infinity();
        return true;
    }
    if (text == "-.inf" || text == "-.Inf") {
        out = -std::numeric_limits<double>::infinity();
        return true;
    }
    if (text == ".nan" || text == ".NaN") {
        out = std::numeric_limits<double>::quiet_NaN();
        return true;
    }
    if (text.empty()) return false;
    // Only plain decimal / exponent forms ("1e-3", "0.5"); strtod would also take "inf", "0x1p3".
    for (char c : text) {
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E')) {
            return false;
        }
    }
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || errno == ERANGE) return false;
    out = v;
    return true;
}

bool parseBool(const std::string& text, bool& out) {
    static const std::set<std::string> kTrue{"true", "True", "TRUE", "yes", "Yes", "on", "On"};
    static const std::set<std::string> kFalse{"false", "False", "FALSE", "no", "No", "off", "Off"};
    if (kTrue.count(text)) {
        out = true;
        return true;
    }
    if (kFalse.count(text)) {
        out = false;
        return true;
    }
    return false;
}

/// "int 5", "string 'abc'", "a list", "a map", "null": what a node looks like, for messages.
std::string describeNode(const YAML::Node& node) {
    if (!node.IsDefined() || node.IsNull()) return "null";
    if (node.IsSequence()) return "a list of " + std::to_string(node.size());
    if (node.IsMap()) return "a map";
    const std::string& text = node.Scalar();
    std::int64_t i;
    double d;
    bool b;
    if (!isQuoted(node)) {
        if (parseInt(text, i)) return "int " + text;
        if (parseDouble(text, d)) return "double " + text;
        if (parseBool(text, b)) return "bool " + text;
    }
    return "string '" + text + "'";
}

[[noreturn]] void typeError(OptionType want, const YAML::Node& node) {
    throw ConfigError(std::string("expected ") + optionTypeName(want) + ", found " +
                      describeNode(node));
}

OptionValue scalarTo(const YAML::Node& node, OptionType want) {
    const std::string& text = node.Scalar();
    switch (want) {
        case OptionType::Bool: {
            bool b;
            if (isQuoted(node) || !parseBool(text, b)) typeError(want, node);
            return b;
        }
        case OptionType::Int: {
            std::int64_t i;
            if (isQuoted(node) || !parseInt(text, i)) typeError(want, node);
            return i;
        }
        case OptionType::Double: {
            double d;
            if (isQuoted(node) || !parseDouble(text, d)) typeError(want, node);
            return d;
        }
        case OptionType::String:
            return text;
        default:
            typeError(want, node);
    }
}

}  // namespace

std::string yamlLocation(const std::string& source, const YAML::Node& node) {
    if (!node.IsDefined()) return source;
    const YAML::Mark mark = node.Mark();
    if (mark.is_null()) return source;
    return source + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

std::vector<YamlEntry> yamlMapEntries(const YAML::Node& map, const std::string& source,
                                      const std::string& what, const std::string& skip_key) {
    std::vector<YamlEntry> entries;
    if (!map.IsDefined() || map.IsNull()) return entries;
    if (!map.IsMap()) {
        throw ConfigError(yamlLocation(source, map) + ": " + what + ": expected a map of keys, found " +
                          describeNode(map));
    }
    for (const auto& item : map) {
        if (!item.first.IsScalar()) {
            throw ConfigError(yamlLocation(source, item.first) + ": " + what +
                              ": keys must be plain names");
        }
        const std::string key = item.first.Scalar();
        if (!skip_key.empty() && key == skip_key) continue;
        entries.push_back({key, item.second, yamlLocation(source, item.first)});
    }
    return entries;
}

OptionValue yamlToOption(const YAML::Node& node, OptionType want) {
    const bool is_list = want == OptionType::DoubleList || want == OptionType::IntList ||
                         want == OptionType::StringList;
    if (!node.IsDefined() || node.IsNull()) {
        if (want == OptionType::String) return std::string();
        if (want == OptionType::DoubleList) return std::vector<double>{};
        if (want == OptionType::IntList) return std::vector<std::int64_t>{};
        if (want == OptionType::StringList) return std::vector<std::string>{};
        typeError(want, node);
    }
    if (node.IsMap()) typeError(want, node);
    if (!is_list) {
        if (!node.IsScalar()) typeError(want, node);
        return scalarTo(node, want);
    }
    if (!node.IsSequence()) typeError(want, node);
    const OptionType element = want == OptionType::DoubleList ? OptionType::Double
                               : want == OptionType::IntList  ? OptionType::Int
                                                              : OptionType::String;
    std::vector<double> doubles;
    std::vector<std::int64_t> ints;
    std::vector<std::string> strings;
    for (std::size_t i = 0; i < node.size(); ++i) {
        const YAML::Node item = node[i];
        if (!item.IsScalar()) {
            throw ConfigError(std::string("expected ") + optionTypeName(want) + ", found " +
                              describeNode(item) + " at element " + std::to_string(i));
        }
        OptionValue v;
        try {
            v = scalarTo(item, element);
        } catch (const ConfigError&) {
            throw ConfigError(std::string("expected ") + optionTypeName(want) + ", found " +
                              describeNode(item) + " at element " + std::to_string(i));
        }
        if (element == OptionType::Double) doubles.push_back(std::get<double>(v));
        if (element == OptionType::Int) ints.push_back(std::get<std::int64_t>(v));
        if (element == OptionType::String) strings.push_back(std::get<std::string>(v));
    }
    if (want == OptionType::DoubleList) return doubles;
    if (want == OptionType::IntList) return ints;
    return strings;
}

void bindEntries(OptionSpec& spec, const std::vector<YamlEntry>& entries, const std::string& label,
                 const std::string& section_where) {
    std::set<std::string> seen;
    for (const auto& entry : entries) {
        const OptionInfo* info = spec.find(entry.key);
        if (info == nullptr) {
            throw ConfigError(entry.where + ": " + label + ": unknown key '" + entry.key +
                              "'; valid keys: " + spec.keyList());
        }
        try {
            spec.set(entry.key, yamlToOption(entry.value, info->type));
        } catch (const ConfigError& e) {
            throw ConfigError(entry.where + ": " + label + ": key '" + entry.key + "': " +
                              e.what());
        }
        seen.insert(entry.key);
    }
    for (const auto& info : spec.options()) {
        if (info.required && seen.count(info.key) == 0) {
            throw ConfigError(section_where + ": " + label + ": missing required key '" +
                              info.key + "' (" + optionTypeName(info.type) + ": " + info.doc +
                              "); valid keys: " + spec.keyList());
        }
    }
}

}  // namespace vdbmap::detail
