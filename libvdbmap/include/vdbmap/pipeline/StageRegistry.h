// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/pipeline/Stage.h"

namespace vdbmap {

using StageFactory = std::function<std::unique_ptr<Stage>()>;

/// The one registry of stages, built-in and plugin alike. Process-wide (the library is
/// shared, so the app and every plugin see the same instance). Thread-safe.
class StageRegistry {
public:
    static StageRegistry& instance();

    struct Entry {
        std::string name;     ///< "texture.mrf"
        std::string summary;  ///< one line
        std::string origin;   ///< "built-in" or the plugin file path
        StageFactory factory;
    };

    /// Registers a stage. Throws InvalidInput if the name is taken or empty.
    void add(const std::string& name, const std::string& summary, StageFactory factory,
             const std::string& origin = "built-in");
    /// Registers T, taking name and summary from an instance.
    template <typename T>
    void add(const std::string& origin = "built-in") {
        T probe;
        add(std::string(probe.name()), std::string(probe.summary()),
            [] { return std::unique_ptr<Stage>(new T()); }, origin);
    }
    bool contains(const std::string& name) const;
    /// Throws ConfigError naming the stage and listing the registered names.
    std::unique_ptr<Stage> create(const std::string& name) const;
    /// Sorted by name.
    std::vector<Entry> entries() const;

private:
    StageRegistry();
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Registers the built-in stages (integration, meshing, export...). Idempotent; called by
/// the pipeline and the apps before use.
void registerBuiltinStages();

}  // namespace vdbmap
