// SPDX-License-Identifier: Apache-2.0
// The plugin's one entry point: name + stage types. The macro emits the extern "C" symbol
// `vdbmap_plugin_info_v1` with the ABI versions the loader checks before registering.
#include <vdbmap/plugin/Plugin.h>

#include "GreetStage.h"
#include "TileSummaryStage.h"

VDBMAP_PLUGIN("template", vdbmap_template::GreetStage, vdbmap_template::TileSummaryStage)
