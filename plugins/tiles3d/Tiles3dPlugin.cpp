// SPDX-License-Identifier: Apache-2.0
// The 3D Tiles plugin's entry point: the only exported symbol of vdbmap_plugin_tiles3d.so.
#include "Tiles3dStage.h"
#include "vdbmap/plugin/Plugin.h"

VDBMAP_PLUGIN("tiles3d", vdbmap::tiles3d::Tiles3dStage)
