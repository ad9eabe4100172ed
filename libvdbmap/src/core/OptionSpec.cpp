// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/core/OptionSpec.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <type_traits>

#include "vdbmap/Error.h"

namespace vdbmap {
namespace {

OptionType typeOfValue(const OptionValue& value) {
    return static_cast<OptionType>(value.index());
}

std::string formatDouble(double v) {
    if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15) {
        // Keep a ".0" so that a double never reads back as an int.
        std::ostringstream out;
        out << static_cast<long long>(v) << ".0";
        return out.str();
    }
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.10g", v);
    return buffer;
}

std::string quote(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

template <typename T, typename F>
std::string formatList(const std::vector<T>& values, F&& format_one) {
    std::string out = "[";
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i > 0) out += ", ";
        out += format_one(values[i]);
    }
    return out + "]";
}

/// Converts `value` to the option's type: exact match, or Int -> Double, IntList -> DoubleList,
/// and an empty list of any element type to any list type (YAML `[]` has no element type).
bool convert(const OptionValue& value, OptionType want, OptionValue& out) {
    const OptionType have = typeOfValue(value);
    if (have == want) {
        out = value;
        return true;
    }
    if (want == OptionType::Double && have == OptionType::Int) {
        out = static_cast<double>(std::get<std::int64_t>(value));
        return true;
    }
    if (want == OptionType::DoubleList && have == OptionType::IntList) {
        const auto& ints = std::get<std::vector<std::int64_t>>(value);
        out = std::vector<double>(ints.begin(), ints.end());
        return true;
    }
    const bool have_list = have == OptionType::DoubleList || have == OptionType::IntList ||
                           have == OptionType::StringList;
    const bool want_list = want == OptionType::DoubleList || want == OptionType::IntList ||
                           want == OptionType::StringList;
    if (have_list && want_list) {
        const bool empty = std::visit(
            [](const auto& v) {
                using V = std::decay_t<decltype(v)>;
                if constexpr (std::is_same_v<V, std::vector<double>> ||
                              std::is_same_v<V, std::vector<std::int64_t>> ||
                              std::is_same_v<V, std::vector<std::string>>) {
                    return v.empty();
                } else {
                    return false;
                }
            },
            value);
        if (empty) {
            if (want == OptionType::DoubleList) out = std::vector<double>{};
            if (want == OptionType::IntList) out = std::vector<std::int64_t>{};
            if (want == OptionType::StringList) out = std::vector<std::string>{};
            return true;
        }
    }
    return false;
}

/// Writes a converted value (of the option's type) into the bound member.
void assign(const OptionInfo& info, const OptionValue& value) {
    std::visit(
        [&value](auto* member) {
            using Member = std::remove_pointer_t<decltype(member)>;
            using Stored = typename detail::OptionStored<Member>::type;
            *member = detail::convertOptionValue<Member>(std::get<Stored>(value));
        },
        info.target);
}

bool fitsInt(std::int64_t v) {
    return v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max();
}

/// An int member (or a list of them) takes only values that fit in 32 bits.
void checkIntRange(const OptionInfo& info, const OptionValue& value) {
    if (std::holds_alternative<int*>(info.target) && !fitsInt(std::get<std::int64_t>(value))) {
        throw ConfigError("option '" + info.key + "': value " + formatOptionValue(value) +
                          " does not fit in a 32-bit int");
    }
    if (std::holds_alternative<std::vector<int>*>(info.target)) {
        for (std::int64_t v : std::get<std::vector<std::int64_t>>(value)) {
            if (!fitsInt(v)) {
                throw ConfigError("option '" + info.key + "': element " + std::to_string(v) +
                                  " does not fit in a 32-bit int");
            }
        }
    }
}

}  // namespace

const char* optionTypeName(OptionType type) {
    switch (type) {
        case OptionType::Bool: return "bool";
        case OptionType::Int: return "int";
        case OptionType::Double: return "double";
        case OptionType::String: return "string";
        case OptionType::DoubleList: return "list<double>";
        case OptionType::IntList: return "list<int>";
        case OptionType::StringList: return "list<string>";
    }
    return "unknown";
}

void OptionSpec::push(OptionInfo info) {
    if (info.key.empty()) throw InvalidInput("OptionSpec: an option has an empty key");
    if (find(info.key) != nullptr) {
        throw InvalidInput("OptionSpec: option '" + info.key + "' is declared twice");
    }
    options_.push_back(std::move(info));
}

const OptionInfo* OptionSpec::find(const std::string& key) const {
    for (const auto& info : options_) {
        if (info.key == key) return &info;
    }
    return nullptr;
}

std::string OptionSpec::keyList() const {
    std::string out;
    for (const auto& info : options_) {
        if (!out.empty()) out += ", ";
        out += info.key;
    }
    return out.empty() ? std::string("(none)") : out;
}

void OptionSpec::set(const std::string& key, const OptionValue& value) {
    const OptionInfo* info = find(key);
    if (info == nullptr) {
        throw ConfigError("unknown option '" + key + "'; valid keys: " + keyList());
    }
    OptionValue converted;
    if (!convert(value, info->type, converted)) {
        throw ConfigError("option '" + key + "': expected " + optionTypeName(info->type) +
                          ", found " + optionTypeName(typeOfValue(value)) + " " +
                          formatOptionValue(value));
    }
    checkIntRange(*info, converted);
    assign(*info, converted);
}

OptionValue OptionSpec::value(const std::string& key) const {
    const OptionInfo* info = find(key);
    if (info == nullptr) {
        throw ConfigError("unknown option '" + key + "'; valid keys: " + keyList());
    }
    return currentValue(*info);
}

OptionValue currentValue(const OptionInfo& info) {
    return std::visit(
        [](const auto* member) -> OptionValue {
            using Member = std::remove_cv_t<std::remove_pointer_t<decltype(member)>>;
            using Stored = typename detail::OptionStored<Member>::type;
            return detail::convertOptionValue<Stored>(*member);
        },
        info.target);
}

std::string formatOptionValue(const OptionValue& value) {
    return std::visit(
        [](const auto& v) -> std::string {
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<V, bool>) {
                return v ? "true" : "false";
            } else if constexpr (std::is_same_v<V, std::int64_t>) {
                return std::to_string(v);
            } else if constexpr (std::is_same_v<V, double>) {
                return formatDouble(v);
            } else if constexpr (std::is_same_v<V, std::string>) {
                return quote(v);
            } else if constexpr (std::is_same_v<V, std::vector<double>>) {
                return formatList(v, formatDouble);
            } else if constexpr (std::is_same_v<V, std::vector<std::int64_t>>) {
                return formatList(v, [](std::int64_t x) { return std::to_string(x); });
            } else {
                return formatList(v, quote);
            }
        },
        value);
}

}  // namespace vdbmap
