// SPDX-License-Identifier: Apache-2.0
#include "SimplifyStage.h"
#include "vdbmap/plugin/Plugin.h"

VDBMAP_PLUGIN("cgal", vdbmap::cgal::SimplifyStage)
