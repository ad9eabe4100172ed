// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace vdbmap {

/// The value types an option can have. YAML scalars and sequences are converted to these.
using OptionValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>,
                                 std::vector<std::int64_t>, std::vector<std::string>>;

/// Type tag of an option, in the order of OptionValue's alternatives.
enum class OptionType { Bool, Int, Double, String, DoubleList, IntList, StringList };

/// The C++ type of the member an option is bound to (int vs int64, vector<int> vs ...).
enum class OptionCxxType { Bool, Int, Int64, Double, String, DoubleVec, IntVec, Int64Vec, StringVec };

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
    void* target = nullptr;     ///< bound member, of C++ type `cxx_type`
    OptionCxxType cxx_type = OptionCxxType::Bool;
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
    void push(OptionInfo info);
    std::vector<OptionInfo> options_;
};

/// The current value of the member an option is bound to.
OptionValue currentValue(const OptionInfo& info);

/// Formats a value for `describe` and report.json ("0.1", "[1, 2]", "\"abc\"", "true").
std::string formatOptionValue(const OptionValue& value);

// ---- implementation ----

namespace detail {
template <typename T>
struct OptionTraits;
template <>
struct OptionTraits<bool> {
    static constexpr OptionType type = OptionType::Bool;
    static OptionValue wrap(bool v) { return v; }
};
template <>
struct OptionTraits<int> {
    static constexpr OptionType type = OptionType::Int;
    static OptionValue wrap(int v) { return static_cast<std::int64_t>(v); }
};
template <>
struct OptionTraits<std::int64_t> {
    static constexpr OptionType type = OptionType::Int;
    static OptionValue wrap(std::int64_t v) { return v; }
};
template <>
struct OptionTraits<double> {
    static constexpr OptionType type = OptionType::Double;
    static OptionValue wrap(double v) { return v; }
};
template <>
struct OptionTraits<std::string> {
    static constexpr OptionType type = OptionType::String;
    static OptionValue wrap(const std::string& v) { return v; }
};
template <>
struct OptionTraits<std::vector<double>> {
    static constexpr OptionType type = OptionType::DoubleList;
    static OptionValue wrap(const std::vector<double>& v) { return v; }
};
template <>
struct OptionTraits<std::vector<int>> {
    static constexpr OptionType type = OptionType::IntList;
    static OptionValue wrap(const std::vector<int>& v) {
        return std::vector<std::int64_t>(v.begin(), v.end());
    }
};
template <>
struct OptionTraits<std::vector<std::string>> {
    static constexpr OptionType type = OptionType::StringList;
    static OptionValue wrap(const std::vector<std::string>& v) { return v; }
};
template <typename T>
constexpr OptionCxxType cxxTypeOf();
template <> constexpr OptionCxxType cxxTypeOf<bool>() { return OptionCxxType::Bool; }
template <> constexpr OptionCxxType cxxTypeOf<int>() { return OptionCxxType::Int; }
template <> constexpr OptionCxxType cxxTypeOf<std::int64_t>() { return OptionCxxType::Int64; }
template <> constexpr OptionCxxType cxxTypeOf<double>() { return OptionCxxType::Double; }
template <> constexpr OptionCxxType cxxTypeOf<std::string>() { return OptionCxxType::String; }
template <> constexpr OptionCxxType cxxTypeOf<std::vector<double>>() { return OptionCxxType::DoubleVec; }
template <> constexpr OptionCxxType cxxTypeOf<std::vector<int>>() { return OptionCxxType::IntVec; }
template <> constexpr OptionCxxType cxxTypeOf<std::vector<std::int64_t>>() { return OptionCxxType::Int64Vec; }
template <> constexpr OptionCxxType cxxTypeOf<std::vector<std::string>>() { return OptionCxxType::StringVec; }
}  // namespace detail

template <typename T>
void OptionSpec::add(const std::string& key, const std::string& doc, T& member, T default_value,
                     const std::string& unit) {
    OptionInfo info;
    info.key = key;
    info.doc = doc;
    info.unit = unit;
    info.type = detail::OptionTraits<T>::type;
    info.required = false;
    info.default_value = detail::OptionTraits<T>::wrap(default_value);
    info.target = &member;
    info.cxx_type = detail::cxxTypeOf<T>();
    member = default_value;
    push(std::move(info));
}

template <typename T>
void OptionSpec::addRequired(const std::string& key, const std::string& doc, T& member,
                             const std::string& unit) {
    OptionInfo info;
    info.key = key;
    info.doc = doc;
    info.unit = unit;
    info.type = detail::OptionTraits<T>::type;
    info.required = true;
    info.default_value = detail::OptionTraits<T>::wrap(T{});
    info.target = &member;
    info.cxx_type = detail::cxxTypeOf<T>();
    push(std::move(info));
}

}  // namespace vdbmap
