// SPDX-License-Identifier: Apache-2.0
#include <unistd.h>

#include <climits>
#include <filesystem>

#include "Commands.h"
#include "vdbmap/plugin/PluginLoader.h"

void addRelocatablePluginDir() {
    char buffer[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", buffer, sizeof(buffer) - 1);
    if (n <= 0) return;
    buffer[n] = '\0';
    const std::filesystem::path exe_dir = std::filesystem::path(buffer).parent_path();
    vdbmap::PluginLoader::addSearchDirectory(exe_dir.parent_path() / "lib" / "vdbmap" / "plugins");
}
