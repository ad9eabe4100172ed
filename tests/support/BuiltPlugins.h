// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace vdbmap::test {

/// The in-tree plugins this build has (VDBMAP_BUILT_PLUGINS, set by tests/Foundation.cmake
/// from the plugin targets that exist). A test that needs one of these fails when it cannot
/// load it; only a plugin the build left out may be missing.
inline std::vector<std::string> builtPlugins() {
    std::vector<std::string> names;
    std::istringstream in(VDBMAP_BUILT_PLUGINS);
    for (std::string name; std::getline(in, name, ',');) {
        if (!name.empty()) names.push_back(name);
    }
    return names;
}

inline bool isBuiltPlugin(const std::string& name) {
    const auto built = builtPlugins();
    return std::find(built.begin(), built.end(), name) != built.end();
}

/// The in-tree plugins whether built or not (plugins/CMakeLists.txt).
inline std::vector<std::string> inTreePlugins() { return {"texture", "semantic", "tiles3d", "cgal"}; }

}  // namespace vdbmap::test
