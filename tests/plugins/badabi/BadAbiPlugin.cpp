// SPDX-License-Identifier: Apache-2.0
// Test plugin built "against another ABI": the struct is written by hand with a wrong
// abi_version, and register_stages would abort the process if the loader ever called it.
#include <cstdlib>

#include "vdbmap/plugin/Plugin.h"

namespace {
int registerNothing(vdbmap_registry*) { std::abort(); }
}  // namespace

VDBMAP_PLUGIN_EXPORT const vdbmap_plugin_info* vdbmap_plugin_info_v1(void) {
    static const vdbmap_plugin_info info = {9999u, OPENVDB_ABI_VERSION_NUMBER, "99.0.0", "badabi",
                                            &registerNothing};
    return &info;
}
