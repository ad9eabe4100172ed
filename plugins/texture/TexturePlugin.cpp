// SPDX-License-Identifier: Apache-2.0
// The texture plugin's entry point: the only exported symbol of vdbmap_plugin_texture.so.
#include "TextureMrfStage.h"
#include "vdbmap/plugin/Plugin.h"

VDBMAP_PLUGIN("texture", vdbmap::texture::TextureMrfStage)
