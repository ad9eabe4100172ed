// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace vdbmap {

/// The run report, written as report.json: versions, resolved config, counts, timings per
/// stage, peak memory. A value sits at a path given as a list of keys, never as one dotted
/// string: a stage name such as "integrate.atsdf" stays one key (`stage(name, key, value)`
/// sets stages.<name>.<key>). Objects are built by setting values at deeper paths, lists
/// with the vector overloads; `setJson` takes ready JSON text. Thread-safe.
class Report {
public:
    Report();
    ~Report();
    Report(const Report&) = delete;
    Report& operator=(const Report&) = delete;

    /// Sets a value at a path given as a list of keys, e.g. {"counts", "faces"}.
    void set(const std::vector<std::string>& path, double value);
    void set(const std::vector<std::string>& path, std::int64_t value);
    void set(const std::vector<std::string>& path, int value) {
        set(path, static_cast<std::int64_t>(value));
    }
    void set(const std::vector<std::string>& path, std::size_t value) {
        set(path, static_cast<std::int64_t>(value));
    }
    void set(const std::vector<std::string>& path, bool value);
    void set(const std::vector<std::string>& path, const std::string& value);
    void set(const std::vector<std::string>& path, const char* value) {
        set(path, std::string(value));
    }
    /// Sets a list (a JSON array) of numbers or strings.
    void set(const std::vector<std::string>& path, const std::vector<double>& values);
    void set(const std::vector<std::string>& path, const std::vector<std::int64_t>& values);
    void set(const std::vector<std::string>& path, const std::vector<std::string>& values);
    /// Sets a JSON value given as text (an object, an array...). Throws InvalidInput if the
    /// text is not valid JSON.
    void setJson(const std::vector<std::string>& path, const std::string& json_text);
    /// Adds `delta` to an integer counter (created at 0).
    void add(const std::vector<std::string>& path, std::int64_t delta);

    /// Convenience for stages: sets stages.<stage>.<key>.
    template <typename T>
    void stage(const std::string& stage_name, const std::string& key, const T& value) {
        set({"stages", stage_name, key}, value);
    }

    /// The whole report as JSON text.
    std::string toJson(int indent = 2) const;
    /// Reads a value back (tests); returns JSON text of the value or "null".
    std::string getJson(const std::vector<std::string>& path) const;
    /// Writes the JSON to `path` atomically (temporary file + rename). Throws IoError.
    void write(const std::filesystem::path& path) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vdbmap
