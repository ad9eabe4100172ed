// SPDX-License-Identifier: Apache-2.0
#pragma once

/// The run-time plugin ABI. A plugin is a shared module `vdbmap_plugin_<name>.so` exporting
/// one extern "C" symbol, `vdbmap_plugin_info_v1`, which returns a pointer to a static
/// `vdbmap_plugin_info`. The loader compares `abi_version` and `openvdb_abi` with its own
/// before it calls `register_stages`. Plugin authors write
///
///     VDBMAP_PLUGIN("texturing", ProjectiveTextureStage, AtlasStage)
///
/// once in one .cpp file and never fill the struct by hand.

#include <openvdb/version.h>

#include <cstdint>
#include <exception>
#include <memory>

#include "vdbmap/Version.h"
#include "vdbmap/pipeline/Stage.h"

#define VDBMAP_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))

/// Opaque handle the loader passes to `register_stages`.
struct vdbmap_registry;

/// C-compatible plugin description. Append-only: never reorder or remove fields.
struct vdbmap_plugin_info {
    std::uint32_t abi_version;                    ///< VDBMAP_PLUGIN_ABI_VERSION at build time
    std::uint32_t openvdb_abi;                    ///< OPENVDB_ABI_VERSION_NUMBER at build time
    const char* vdbmap_version;                   ///< informational, "0.1.0"
    const char* name;                             ///< plugin name, e.g. "texture"
    int (*register_stages)(vdbmap_registry* reg); ///< 0 = ok; never throws
};

/// Name of the entry symbol the loader looks up.
#define VDBMAP_PLUGIN_ENTRY_SYMBOL "vdbmap_plugin_info_v1"

namespace vdbmap::detail {

/// Creates a stage of a plugin's type; a plain function pointer keeps std::function out of
/// the C boundary.
using PluginStageFactory = Stage* (*)();

/// Registers one stage type from a plugin into the registry behind `reg` (origin = the
/// plugin file). Throws on a duplicate name; the VDBMAP_PLUGIN macro catches everything.
void registerPluginStage(vdbmap_registry* reg, PluginStageFactory factory);
/// Records why registration failed, for the loader's PluginError. Never throws.
void setPluginRegistrationError(vdbmap_registry* reg, const char* message) noexcept;

template <typename T>
Stage* createPluginStage() {
    return new T();
}

/// Registers every listed stage type; returns 0 on success, 1 after any exception (the
/// registry keeps the message, see lastPluginError()).
template <typename... Stages>
int registerPluginStages(vdbmap_registry* reg) noexcept {
    try {
        (registerPluginStage(reg, &createPluginStage<Stages>), ...);
        return 0;
    } catch (const std::exception& e) {
        setPluginRegistrationError(reg, e.what());
        return 1;
    } catch (...) {
        setPluginRegistrationError(reg, "unknown exception");
        return 1;
    }
}

}  // namespace vdbmap::detail

/// Emits the plugin entry point for the listed Stage types.
#define VDBMAP_PLUGIN(PLUGIN_NAME, ...)                                                    \
    VDBMAP_PLUGIN_EXPORT const vdbmap_plugin_info* vdbmap_plugin_info_v1(void) {           \
        static const vdbmap_plugin_info info = {                                           \
            VDBMAP_PLUGIN_ABI_VERSION, OPENVDB_ABI_VERSION_NUMBER, VDBMAP_VERSION_STRING,   \
            PLUGIN_NAME, &::vdbmap::detail::registerPluginStages<__VA_ARGS__>};             \
        return &info;                                                                      \
    }
