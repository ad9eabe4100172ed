// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>

namespace vdbmap::test {

/// The path of in-tree plugin `name`'s shared library in this build (VDBMAP_PLUGIN_BUILD_DIR).
inline std::string builtPluginPath(const std::string& name) {
    return (std::filesystem::path(VDBMAP_PLUGIN_BUILD_DIR) / ("vdbmap_plugin_" + name + ".so")).string();
}

}  // namespace vdbmap::test
