// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace vdbmap {

/// Finds and loads run-time plugins into StageRegistry::instance().
///  - A spec with a '/' or ending in ".so" is a path.
///  - A bare name `foo` is looked up as `vdbmap_plugin_foo.so` in each directory of
///    $VDBMAP_PLUGIN_PATH (':'-separated), then in the build-tree plugin directory next to
///    the library, then in <prefix>/lib/vdbmap/plugins.
/// Loading: dlopen(RTLD_NOW | RTLD_LOCAL) -> dlsym(VDBMAP_PLUGIN_ENTRY_SYMBOL) -> check
/// abi_version and openvdb_abi -> register_stages. Every failure throws PluginError naming the
/// file, what was expected and what was found; nothing is registered then. Handles are never
/// closed (stages from the plugin may outlive any scope). Loading the same file twice is a
/// no-op.
class PluginLoader {
public:
    /// Returns the resolved path of the loaded plugin.
    static std::filesystem::path load(const std::string& spec);
    /// The directories searched for bare names, in order.
    static std::vector<std::filesystem::path> searchPath();
};

}  // namespace vdbmap
