// SPDX-License-Identifier: Apache-2.0
// Entry point of the semantic plugin (paper Sec. 6).
#include "SemanticMrfStage.h"
#include "vdbmap/plugin/Plugin.h"

VDBMAP_PLUGIN("semantic", vdbmap::semantic::SemanticMrfStage)
