// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace vdbmap {

/// Finds and loads run-time plugins into StageRegistry::instance().
///  - A spec with a '/' or ending in ".so" is a path (relative paths: relative to `base_dir`).
///  - A bare name `foo` is looked up as `vdbmap_plugin_foo.so` in each directory of
///    $VDBMAP_PLUGIN_PATH (':'-separated), then in the directories added with
///    addSearchDirectory() (the app adds `<exe dir>/../lib/vdbmap/plugins`), then in the
///    build-tree plugin directory, then in `<install prefix>/lib/vdbmap/plugins`.
/// Loading: dlopen(RTLD_NOW | RTLD_LOCAL) -> dlsym(VDBMAP_PLUGIN_ENTRY_SYMBOL) -> check
/// abi_version and openvdb_abi -> register_stages. Every failure throws PluginError naming the
/// file, what was expected and what was found; nothing is registered then. Handles are never
/// closed once a plugin has registered stages (stages from the plugin may outlive any scope).
/// Loading the same file twice is a no-op. Thread-safe.
class PluginLoader {
public:
    /// Loads one plugin; returns the resolved (canonical) path of the loaded file.
    /// Throws PluginError.
    static std::filesystem::path load(const std::string& spec,
                                      const std::filesystem::path& base_dir = {});
    /// Resolves a spec to a file without loading it. Throws PluginError if not found.
    static std::filesystem::path resolve(const std::string& spec,
                                         const std::filesystem::path& base_dir = {});
    /// The directories searched for bare names, in order (existing or not).
    static std::vector<std::filesystem::path> searchPath();
    /// Adds a directory searched after $VDBMAP_PLUGIN_PATH (the app adds its relocatable
    /// `<exe dir>/../lib/vdbmap/plugins`). Duplicates are ignored.
    static void addSearchDirectory(const std::filesystem::path& dir);
    /// Plugin names (`foo` for `vdbmap_plugin_foo.so`) found in the search path, first
    /// directory wins, sorted. Used by `vdbmap describe` to list every available stage.
    static std::vector<std::string> discover();
    /// Canonical paths of the plugins loaded so far.
    static std::vector<std::filesystem::path> loaded();
};

}  // namespace vdbmap
