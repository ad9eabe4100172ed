// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "vdbmap/plugin/Plugin.h"

/// What the loader hands to a plugin's `register_stages`: stages are collected here first and
/// moved into the StageRegistry only when the whole registration succeeded, so that a failing
/// plugin registers nothing.
struct vdbmap_registry {
    std::string origin;  ///< the plugin file
    std::vector<vdbmap::detail::PluginStageFactory> factories;
    std::string error;  ///< set by setPluginRegistrationError
};
