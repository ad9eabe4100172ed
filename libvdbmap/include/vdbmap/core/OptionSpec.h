// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace vdbmap {

/// The value types an option can have. YAML scalars and sequences are converted to these.
using OptionValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>,
                                 std::vector<std::int64_t>, std::vector<std::string>>;

/// Type tag of an option, in the order of OptionValue's alternatives.
enum class OptionType { Bool, Int, Double, String, DoubleList, IntList, StringList };

/// The stage member an option is bound to: one typed pointer per supported member type
/// (an int member holds an Int value, a vector<int> an IntList...).
using OptionTarget =
    std::variant<bool*, int*, std::int64_t*, double*, std::string*, std::vector<double>*,
                 std::vector<int>*, std::vector<std::int64_t>*, std::vector<std::string>*>;

/// Human-readable name of an option type ("bool", "int", "double", "string", "list<double>"...).
const char* optionTypeName(OptionType type);

/// One declared option: key, doc, unit, type, default, and the stage member it is bound to.
struct OptionInfo {
    std::string key;            ///< YAML key, e.g. "voxel_size_m"
    std::string doc;            ///< one-line description
    std::string unit;           ///< "m", "deg", "px", "" ...
    OptionType type;
    bool required = false;      ///< no default; a missing key is a ConfigError
    OptionValue default_value;  ///< meaningful when !required
    OptionTarget target;        ///< the bound member
};

/// The options of one stage (PDAL ProgramArgs, kiss-icp config structs). A stage declares
/// each option once, bound to a member; the pipeline fills the members from YAML and
/// `vdbmap describe` prints the spec. Defaults are written into the member at declaration.
class OptionSpec {
public:
    /// Declares an optional option and assigns `default_value` to `member`.
    /// Supported T: bool, int, std::int64_t, double, std::string, std::vector<double>,
    /// std::vector<int>, std::vector<std::string>. Throws InvalidInput on a duplicate key.
    template <typename T>
    void add(const std::string& key, const std::string& doc, T& member, T default_value,
             const std::string& unit = "");

    /// Declares a required option (no default).
    template <typename T>
    void addRequired(const std::string& key, const std::string& doc, T& member,
                     const std::string& unit = "");

    /// Assigns a value to the bound member. The value's alternative must match the option's
    /// type, except that an Int converts to Double (and IntList to DoubleList). Throws
    /// ConfigError naming the key, the expected type and the type found.
    void set(const std::string& key, const OptionValue& value);

    /// The current value of the bound member (after defaults and binding), for report.json.
    /// Throws ConfigError for an unknown key.
    OptionValue value(const std::string& key) const;

    /// Nullptr if no such key.
    const OptionInfo* find(const std::string& key) const;
    const std::vector<OptionInfo>& options() const { return options_; }
    /// "a, b, c": every valid key, for error messages.
    std::string keyList() const;

private:
    template <typename T>
    static OptionInfo bind(const std::string& key, const std::string& doc, T& member,
                           const T& default_value, bool required, const std::string& unit);
    void push(OptionInfo info);
    std::vector<OptionInfo> options_;
};

/// The current value of the member an option is bound to.
OptionValue currentValue(const OptionInfo& info);

/// Formats a value for `describe` and report.json ("0.1", "[1, 2]", "\"abc\"", "true").
std::string formatOptionValue(const OptionValue& value);

// ---- implementation ----

namespace detail {
/// The OptionValue alternative that holds the value of a member of type T: T itself, except
/// int -> std::int64_t and std::vector<int> -> std::vector<std::int64_t>.
template <typename T>
struct OptionStored {
    using type = T;
};
template <>
struct OptionStored<int> {
    using type = std::int64_t;
};
template <>
struct OptionStored<std::vector<int>> {
    using type = std::vector<std::int64_t>;
};

/// Converts between a member's type and its stored type (a cast, or element-wise for lists).
template <typename To, typename From>
To convertOptionValue(const From& value) {
    if constexpr (std::is_same_v<To, From>) {
        return value;
    } else if constexpr (std::is_arithmetic_v<From>) {
        return static_cast<To>(value);
    } else {
        return To(value.begin(), value.end());
    }
}
}  // namespace detail

template <typename T>
OptionInfo OptionSpec::bind(const std::string& key, const std::string& doc, T& member,
                            const T& default_value, bool required, const std::string& unit) {
    static_assert(std::is_constructible_v<OptionTarget, T*>,
                  "OptionSpec: unsupported option type (see OptionSpec::add)");
    OptionInfo info;
    info.key = key;
    info.doc = doc;
    info.unit = unit;
    info.required = required;
    info.default_value =
        detail::convertOptionValue<typename detail::OptionStored<T>::type>(default_value);
    info.type = static_cast<OptionType>(info.default_value.index());
    info.target = &member;
    return info;
}

template <typename T>
void OptionSpec::add(const std::string& key, const std::string& doc, T& member, T default_value,
                     const std::string& unit) {
    OptionInfo info = bind(key, doc, member, default_value, false, unit);
    member = default_value;
    push(std::move(info));
}

template <typename T>
void OptionSpec::addRequired(const std::string& key, const std::string& doc, T& member,
                             const std::string& unit) {
    push(bind(key, doc, member, T{}, true, unit));
}

}  // namespace vdbmap
